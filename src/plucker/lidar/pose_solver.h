// Robust Levenberg-Marquardt over one scan pose T_w_s, for scan-to-map registration.
//
// Minimises F(T) = 1/2 sum_i rho(|r_i(T)|^2), each r_i a ceres::CostFunction of at most 3 rows on
// the 7-value pose block (factors/lidar_factors.h), rho a ceres::LossFunction (nullptr: rho(s) =
// s), in the tangent of the PoseManifold: each iteration solves (H + lambda diag(H)) dx = -g and
// keeps the step when F decreases (lambda / 10), else lambda * 10. ceres::Solve reaches the same
// minimum (PoseSolverTest.MatchesCeresSolve) at several ms more per scan.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>

#include <memory>
#include <string>
#include <vector>

#include "plucker/geometry/se3.h"

namespace plucker {
namespace lidar {

struct PoseSolverOptions {
  int max_iterations = 4;            // LM iterations (accepted or rejected steps)
  double function_tolerance = 1e-6;  // stop when the relative cost decrease is below this
  double step_tolerance = 1e-7;      // stop when |dx| (rad, m) is below this
  double initial_lambda = 1e-4;      // LM damping relative to diag(H)
};

// The reweighted normal equations of the residuals at one pose, in the tangent (dtheta, dt):
//   H = sum_i w_i J_i^T J_i,  g = sum_i w_i J_i^T r_i,  w_i = rho'(|r_i|^2),  cost = F(T).
struct NormalEquations {
  Matrix6d H = Matrix6d::Zero();
  Vector6d g = Vector6d::Zero();
  double cost = 0.0;
  int num_residuals = 0;  // rows over all residual blocks
};

// False when a residual fails to evaluate or the cost, H or g is not finite.
bool EvaluateNormalEquations(const std::vector<std::unique_ptr<ceres::CostFunction>>& residuals,
                             const ceres::LossFunction* loss, const SE3d& T_w_s,
                             NormalEquations* normal_equations);

struct PoseSolverSummary {
  bool usable = false;  // false: a residual failed to evaluate or the normal equations are singular
  std::string message;  // why not usable
  int iterations = 0;
  double initial_cost = 0.0, final_cost = 0.0;
  // At the returned pose, with its robust weights (what the degeneracy analysis takes).
  NormalEquations normal_equations;
};

PoseSolverSummary SolvePose(const std::vector<std::unique_ptr<ceres::CostFunction>>& residuals,
                            const ceres::LossFunction* loss, const PoseSolverOptions& options,
                            SE3d* T_w_s);

}  // namespace lidar
}  // namespace plucker
