// Diagnostics: the per-frame counts of WindowFrameResult, the IMU chi-square of the newest keyframe
// and the covariance of the newest pose.
#include <ceres/covariance.h>

#include "plucker/window/window_internal.h"

namespace plucker {
namespace window {

using internal::ResidualSpec;

// Whitened squared residual of the IMU factor into the newest keyframe (0 if none).
double SlidingWindowEstimator::Impl::NewestImuChi2() const {
  if (!opt.inertial || keyframes.size() < 2) return 0.0;
  std::vector<ResidualSpec> r;
  AppendInertialResiduals(keyframes.size() - 1, &r);
  if (r.empty() || r.front().cost->num_residuals() != 15) return 0.0;
  std::vector<const double*> params(r.front().blocks.begin(), r.front().blocks.end());
  Eigen::Matrix<double, 15, 1> res;
  if (!r.front().cost->Evaluate(params.data(), res.data(), nullptr)) return 0.0;
  return res.squaredNorm();
}

void SlidingWindowEstimator::Impl::FillCounts(WindowFrameResult* r) const {
  r->window_points = static_cast<int>(points.size());
  r->window_lines = static_cast<int>(lines.size());
  r->window_keyframes = static_cast<int>(keyframes.size());
  r->retained_poses = static_cast<int>(retained.size());
  r->prior_lines = prior_lines;
}

std::optional<Eigen::Matrix<double, 6, 6>> SlidingWindowEstimator::NewestPoseCovariance() const {
  // Not const inside: BuildProblem marks the observations that cannot be evaluated as outliers,
  // as the next window solve would (kept so: the trajectories do not change).
  Impl& m = *impl_;
  if (m.keyframes.empty()) return std::nullopt;
  ceres::Problem problem(Impl::ProblemOptions());
  m.BuildProblem(&problem, false);
  double* pose = m.keyframes.back()->pose;
  if (!problem.HasParameterBlock(pose)) return std::nullopt;
  // Inertial: the gauge (position and yaw) held on the oldest keyframe, its roll and pitch free.
  RollPitchPoseManifold roll_pitch;
  if (m.opt.inertial && m.keyframes.size() > 1 &&
      problem.HasParameterBlock(m.keyframes.front()->pose)) {
    problem.SetManifold(m.keyframes.front()->pose, &roll_pitch);
  }
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::SPARSE_QR;  // fails (nullopt) when the information is rank-deficient
  co.apply_loss_function = true;
  ceres::Covariance covariance(co);
  const std::vector<std::pair<const double*, const double*>> blocks = {{pose, pose}};
  if (!covariance.Compute(blocks, &problem)) return std::nullopt;
  Eigen::Matrix<double, 6, 6, Eigen::RowMajor> c;
  if (!covariance.GetCovarianceBlockInTangentSpace(pose, pose, c.data())) return std::nullopt;
  return Eigen::Matrix<double, 6, 6>(c);
}

}  // namespace window
}  // namespace plucker
