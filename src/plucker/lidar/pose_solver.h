// Robust Levenberg-Marquardt over one scan pose T_w_s, for scan-to-map registration.
//
// Minimises F(T) = 1/2 sum_i rho(|r_i(T)|^2), each r_i a point-to-plane or point-to-edge residual
// (PlaneResidual, EdgeResidual: factors/lidar_factors.h, the values behind PointToPlaneFactor and
// PointToEdgeFactor, whose tangent Jacobians are summed straight into the normal equations), rho
// a ceres::LossFunction (nullptr: rho(s) = s), in the tangent of the PoseManifold: each iteration
// solves (H + lambda diag(H)) dx = -g and keeps the step when F decreases (lambda / 10), else
// lambda * 10. ceres::Solve over the factors reaches the same minimum
// (PoseSolverTest.MatchesCeresSolve) at several ms more per scan.
#pragma once

#include <ceres/loss_function.h>

#include <string>
#include <vector>

#include "plucker/factors/lidar_factors.h"
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
struct LidarResiduals {  // planes first, then edges (the order of summation)
  std::vector<PlaneResidual> planes;
  std::vector<EdgeResidual> edges;
  bool empty() const { return planes.empty() && edges.empty(); }
};

struct NormalEquations {
  Matrix6d H = Matrix6d::Zero();
  Vector6d g = Vector6d::Zero();
  double cost = 0.0;
  int num_residuals = 0;  // rows over all residual blocks
};

// False when a residual fails to evaluate or the cost, H or g is not finite.
bool EvaluateNormalEquations(const LidarResiduals& residuals, const ceres::LossFunction* loss,
                             const SE3d& T_w_s, NormalEquations* normal_equations);

struct PoseSolverSummary {
  bool usable = false;  // false: non-finite normal equations, or singular ones
  std::string message;  // why not usable
  int iterations = 0;
  double initial_cost = 0.0, final_cost = 0.0;
  // At the returned pose, with its robust weights (what the degeneracy analysis takes).
  NormalEquations normal_equations;
};

PoseSolverSummary SolvePose(const LidarResiduals& residuals, const ceres::LossFunction* loss,
                            const PoseSolverOptions& options, SE3d* T_w_s);

}  // namespace lidar
}  // namespace plucker
