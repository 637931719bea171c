// Motion-only refinement of one pose against held landmarks: the tracking step of the sliding
// window (docs/vo.md, docs/vio.md), for `plucker vo` and `plucker vio` alike.
//
// A dense Levenberg-Marquardt on the 6-DoF PoseManifold tangent, without a Ceres problem: the
// verified factors (PointReprojectionFactor[VI], AnchoredLineFactor[VI], the extrinsic held) are
// evaluated in place with only the pose's Jacobian requested, taken to the tangent by
// PoseManifold::PlusJacobian once per iteration, whitened by the robust loss (Ceres' Corrector
// rule, so the cost and the normal equations are those Ceres builds) and summed into a 6x6
// system. The step control is Ceres' LM: the damping diag(H) / radius, the radius updated from
// the ratio of the actual to the model cost decrease, the same function, gradient and parameter
// tolerances; a step at which a residual cannot be evaluated (a point behind the camera) is
// refused like a failed Ceres step. No I/O, no timing.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>

#include <vector>

namespace plucker {
namespace window {

// One observation: a cost function with the parameter blocks (7 pose, kN landmark), the
// landmark held at `landmark` (not owned; must outlive the call). The residual is 2-dimensional
// and robustified. Or a prior on the pose alone (landmark nullptr): a cost with 6 residuals on
// the 7-value pose block, not robustified (e.g. the IMU prediction of the visual-inertial mode).
struct PoseTerm {
  const ceres::CostFunction* cost = nullptr;
  const double* landmark = nullptr;
};

struct PoseRefinementOptions {
  int max_iterations = 8;  // iterations (accepted or refused steps), as Ceres counts them
  double function_tolerance = 1e-6;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;
  double initial_trust_region_radius = 1e4;
  double min_relative_decrease = 1e-3;
};

struct PoseRefinementSummary {
  bool ok = false;  // false: no term could be evaluated at the start (the pose is unchanged)
  int iterations = 0;
  double initial_cost = 0.0;  // 1/2 sum rho(|r|^2), as Ceres reports it
  double final_cost = 0.0;
};

// Refines `pose` (7 values, PoseManifold) in place. `loss` may be null (no robust loss).
// Throws std::invalid_argument for a term that is neither an observation (2 residuals, 2
// parameter blocks with a 7-value first one, a landmark) nor a prior (6 residuals, one 7-value
// block, no landmark).
PoseRefinementSummary RefinePose(const std::vector<PoseTerm>& terms,
                                 const ceres::LossFunction* loss,
                                 const PoseRefinementOptions& options, double* pose);

}  // namespace window
}  // namespace plucker
