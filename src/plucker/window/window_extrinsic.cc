// Online estimation of the camera-body extrinsic T_b_c (InertialOptions::estimate_extrinsic;
// docs/vio.md): its prior, when it is freed, and the visual factors on the extrinsic block.
#include <ceres/autodiff_cost_function.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "plucker/factors/held_extrinsic_factor.h"
#include "plucker/factors/point_reprojection_factor.h"
#include "plucker/factors/time_offset_factor.h"
#include "plucker/window/window_factors_internal.h"
#include "plucker/window/window_internal.h"

namespace plucker {
namespace window {

using internal::PosePriorResidual;
using internal::ResidualSpec;

// The extrinsic back to InertialOptions::T_b_c, held; with estimation, its prior: r = S
// Minus(T_b_c, T_b_c given), S = diag(1 / sigma), the verified MarginalizationPrior of that
// residual alone (nothing marginalized: the prior is the residual's linearisation, exact here
// because the residual is linear in the PoseManifold Minus).
void SlidingWindowEstimator::Impl::ResetExtrinsic() {
  if (!opt.inertial) return;
  T_b_c = opt.inertial->T_b_c;
  T_b_c.ToParameters(extrinsic);
  extrinsic_free = false;
  if (!opt.inertial->estimate_extrinsic || extrinsic_prior) return;
  Vector6d sigma;
  sigma << Eigen::Vector3d::Constant(opt.inertial->extrinsic_rotation_sigma),
      Eigen::Vector3d::Constant(opt.inertial->extrinsic_translation_sigma);
  const Eigen::Matrix<double, 6, 6> S = sigma.cwiseInverse().asDiagonal();
  std::vector<double> x0(extrinsic, extrinsic + 7);
  ceres::AutoDiffCostFunction<PosePriorResidual, 6, 7> cost(new PosePriorResidual{T_b_c, S});
  extrinsic_prior = std::make_unique<MarginalizationPrior>(MarginalizationPrior::Build(
      {{x0.data(), 7, &pose_manifold}}, {{&cost, nullptr, {x0.data()}}}, {}));
}

// Rotation excitation of the window: the second singular value (deg) of the keyframes' body
// rotation vectors relative to the oldest keyframe (0 unless they turned about two axes).
double SlidingWindowEstimator::Impl::RotationSpanDeg() const {
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  const Eigen::Quaterniond q0 = SE3d::FromParameters(keyframes.front()->pose).rotation();
  for (const auto& f : keyframes) {
    const Eigen::Vector3d w =
        LogSO3<double>(q0.conjugate() * SE3d::FromParameters(f->pose).rotation());
    M += w * w.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(M);
  return std::sqrt(std::max(eig.eigenvalues()(1), 0.0)) * 180.0 / M_PI;
}

// Frees the extrinsic for good once the window has rotated enough (see InertialOptions).
void SlidingWindowEstimator::Impl::UpdateExtrinsicFree() {
  if (!opt.inertial || !opt.inertial->estimate_extrinsic || extrinsic_free) return;
  extrinsic_free = RotationSpanDeg() >= opt.inertial->extrinsic_min_rotation_deg;
}

// After a solve: the frames see the camera through the new estimate.
void SlidingWindowEstimator::Impl::SyncExtrinsic() {
  if (!extrinsic_free) return;
  T_b_c = SE3d::FromParameters(extrinsic);
  T_b_c.ToParameters(extrinsic);  // normalized
  for (auto& f : keyframes) f->T_b_c = T_b_c;
}

// With the extrinsic free: the visual residuals (held-extrinsic factors on pose and landmark)
// become the VI factors on (pose, extrinsic block, landmark).
void SlidingWindowEstimator::Impl::UseExtrinsicBlock(std::vector<ResidualSpec>* residuals) {
  if (!extrinsic_free && !TimeOffsetOn()) return;
  for (ResidualSpec& r : *residuals) {
    if (r.frame == nullptr) continue;
    if (!TimeOffsetOn()) {
      if (r.is_point) {
        const sensor::PointObservation& p = r.frame->input.points[r.observation];
        r.cost.reset(PointReprojectionFactorVI::Create(K, p.uv, PointSqrtInfo(p)));
      } else {
        const sensor::SegmentObservation& seg = r.frame->input.segments[r.observation];
        r.cost.reset(AnchoredLineFactorVI::Create(K, seg.s_px, seg.e_px,
                                                  LineSqrtInfo(*lines.at(seg.line_id)),
                                                  lines.at(seg.line_id)->anchor));
      }
      r.blocks = {r.blocks[0], extrinsic, r.blocks[1]};
      continue;
    }
    // The time-offset factors (on the frame's velocities, filled in by MakeFrame).
    ceres::CostFunction* vi;
    if (r.is_point) {
      const sensor::PointObservation& p = r.frame->input.points[r.observation];
      vi = PointReprojectionFactorVITimeOffset::Create(
          K, p.uv, p.uv_velocity.value_or(Eigen::Vector2d::Zero()), PointSqrtInfo(p));
    } else {
      const sensor::SegmentObservation& seg = r.frame->input.segments[r.observation];
      vi = AnchoredLineFactorVITimeOffset::Create(
          K, seg.s_px, seg.e_px, seg.s_velocity.value_or(Eigen::Vector2d::Zero()),
          seg.e_velocity.value_or(Eigen::Vector2d::Zero()), LineSqrtInfo(*lines.at(seg.line_id)),
          lines.at(seg.line_id)->anchor);
    }
    if (extrinsic_free) {
      r.cost.reset(vi);
      r.blocks = {r.blocks[0], extrinsic, time_offset, r.blocks[1]};
    } else if (r.is_point) {
      r.cost.reset(new HeldExtrinsicTimeOffsetFactor<3>(vi, T_b_c));
      r.blocks = {r.blocks[0], time_offset, r.blocks[1]};
    } else {
      r.cost.reset(new HeldExtrinsicTimeOffsetFactor<6>(vi, T_b_c));
      r.blocks = {r.blocks[0], time_offset, r.blocks[1]};
    }
  }
}

SE3d SlidingWindowEstimator::ExtrinsicEstimate() const {
  if (!impl_->opt.inertial) throw std::logic_error("ExtrinsicEstimate: not in the inertial mode");
  return impl_->T_b_c;
}

bool SlidingWindowEstimator::ExtrinsicFree() const { return impl_->extrinsic_free; }

}  // namespace window
}  // namespace plucker
