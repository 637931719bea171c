// The residuals of the window (observations, pose priors, retained line observations) and the
// Ceres problem assembled from them, with first-estimate Jacobians on the blocks of the prior.
#include <ceres/autodiff_cost_function.h>

#include <algorithm>
#include <cmath>

#include "plucker/factors/held_extrinsic_factor.h"
#include "plucker/factors/point_reprojection_factor.h"
#include "plucker/window/window_factors_internal.h"
#include "plucker/window/window_internal.h"

namespace plucker {
namespace window {
namespace {

// (|t_1 - t_0| - d0) / sigma on a pose block (7 values, translation at 4..6), t_0 held.
struct StartScaleResidual {
  Eigen::Vector3d t0;
  double d0, inv_sigma;
  template <typename T>
  bool operator()(const T* pose, T* r) const {
    const T dx = pose[4] - T(t0.x()), dy = pose[5] - T(t0.y()), dz = pose[6] - T(t0.z());
    r[0] = (ceres::sqrt(dx * dx + dy * dy + dz * dz) - T(d0)) * T(inv_sigma);
    return true;
  }
};

}  // namespace

using internal::FirstEstimateCost;
using internal::Frame;
using internal::ObservationBlock;
using internal::PosePriorResidual;
using internal::ResidualSpec;
using internal::RetainedPose;

ceres::CostFunction* SlidingWindowEstimator::Impl::PointCost(
    const sensor::PointObservation& p) const {
  if (!opt.inertial) return PointReprojectionFactor::Create(K, p.uv, PointSqrtInfo(p));
  // With the time offset: the observation moved by the current estimate, uv - td v.
  const Eigen::Vector2d uv = TimeOffsetOn() && p.uv_velocity
                                 ? Eigen::Vector2d(p.uv - time_offset[0] * *p.uv_velocity)
                                 : p.uv;
  return new HeldExtrinsicFactor<3>(PointReprojectionFactorVI::Create(K, uv, PointSqrtInfo(p)),
                                    T_b_c);
}

ceres::CostFunction* SlidingWindowEstimator::Impl::LineCost(const sensor::SegmentObservation& s,
                                                            const internal::LineLandmark& l) const {
  const LineAnchor& anchor = l.anchor;
  if (!opt.inertial) return AnchoredLineFactor::Create(K, s.s_px, s.e_px, LineSqrtInfo(l), anchor);
  if (TimeOffsetOn() && s.s_velocity && s.e_velocity) {
    const double td = time_offset[0];
    return new HeldExtrinsicFactor<6>(
        AnchoredLineFactorVI::Create(K, s.s_px - td * *s.s_velocity, s.e_px - td * *s.e_velocity,
                                     LineSqrtInfo(l), anchor),
        T_b_c);
  }
  return new HeldExtrinsicFactor<6>(
      AnchoredLineFactorVI::Create(K, s.s_px, s.e_px, LineSqrtInfo(l), anchor), T_b_c);
}

void SlidingWindowEstimator::Impl::AppendFrameResiduals(Frame* f, bool with_points, bool with_lines,
                                                        std::vector<ResidualSpec>* out) const {
  if (with_points) {
    for (std::size_t i = 0; i < f->input.points.size(); ++i) {
      if (f->point_outlier[i]) continue;
      const auto it = points.find(f->input.points[i].point_id);
      if (it == points.end()) continue;
      ResidualSpec r;
      r.cost.reset(PointCost(f->input.points[i]));
      // Blocks from a temporary vector throughout: GCC 12 warns (-Wnonnull, a false positive) on
      // assigning an initializer list to the fresh vector here.
      r.blocks = std::vector<double*>{f->pose, it->second->p};
      r.frame = f;
      r.observation = static_cast<int>(i);
      out->push_back(std::move(r));
    }
  }
  if (with_lines) {
    for (std::size_t i = 0; i < f->input.segments.size(); ++i) {
      if (f->segment_outlier[i]) continue;
      const auto it = lines.find(f->input.segments[i].line_id);
      if (it == lines.end()) continue;
      const auto& s = f->input.segments[i];
      ResidualSpec r;
      r.cost.reset(LineCost(s, *it->second));
      r.blocks = std::vector<double*>{f->pose, it->second->block};
      r.frame = f;
      r.observation = static_cast<int>(i);
      r.is_point = false;
      out->push_back(std::move(r));
    }
  }
  AppendRightResiduals(f, with_points, with_lines, out);
  if (f->input.T_w_c_prior) {
    ResidualSpec r;
    r.cost.reset(new ceres::AutoDiffCostFunction<PosePriorResidual, 6, 7>(
        new PosePriorResidual{*f->input.T_w_c_prior, f->input.prior_sqrt_information}));
    r.robust = false;
    r.blocks = std::vector<double*>{f->pose};
    out->push_back(std::move(r));
  }
}

// The observations of the retained poses whose line exists (and, when `only` is given, is in
// it), as residuals on (retained pose, line).
void SlidingWindowEstimator::Impl::AppendRetainedResiduals(std::vector<ResidualSpec>* out,
                                                           const std::set<int>* only,
                                                           const RetainedPose* from) const {
  for (const auto& rp : retained) {
    if (from && rp.get() != from) continue;
    for (const sensor::SegmentObservation& seg : rp->segments) {
      const auto it = lines.find(seg.line_id);
      if (it == lines.end() || (only && !only->count(seg.line_id))) continue;
      ResidualSpec r;
      r.cost.reset(LineCost(seg, *it->second));
      r.blocks = std::vector<double*>{rp->pose, it->second->block};
      r.is_point = false;
      out->push_back(std::move(r));
    }
  }
}

std::vector<const double*> SlidingWindowEstimator::Impl::FirstEstimatesOf(
    const std::vector<double*>& blocks) const {
  std::vector<const double*> out(blocks.size(), nullptr);
  if (!opt.first_estimate_jacobians) return out;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const auto it = fe.find(blocks[i]);
    if (it != fe.end()) out[i] = it->second.data();
  }
  return out;
}

bool SlidingWindowEstimator::Impl::HasPosePrior() const {
  for (const auto& f : keyframes)
    if (f->input.T_w_c_prior) return true;
  return false;
}

// Builds the window problem into `problem` (culling what cannot be evaluated first). Returns
// the number of residual blocks; `observations` (optional): the keyframes' observation blocks.
int SlidingWindowEstimator::Impl::BuildProblem(ceres::Problem* problem, bool hold_gauge,
                                               std::vector<ObservationBlock>* observations) {
  std::vector<ResidualSpec> residuals;
  for (auto& f : keyframes) AppendFrameResiduals(f.get(), true, opt.use_lines, &residuals);
  if (opt.inertial) {
    for (std::size_t k = 0; k < keyframes.size(); ++k) AppendInertialResiduals(k, &residuals);
  }
  AppendRetainedResiduals(&residuals);
  UseExtrinsicBlock(&residuals);
  if (extrinsic_free) {
    ResidualSpec r;
    r.cost.reset(extrinsic_prior->CreateCostFunction());
    r.robust = false;
    r.blocks = std::vector<double*>{extrinsic};
    residuals.push_back(std::move(r));
  }
  if (TimeOffsetOn()) {
    ResidualSpec r;
    r.cost.reset(TimeOffsetPrior());
    r.robust = false;
    r.blocks = std::vector<double*>{time_offset};
    residuals.push_back(std::move(r));
  }
  int n = 0;
  for (ResidualSpec& r : residuals) {
    if (r.frame != nullptr) {
      double res[2];
      std::vector<const double*> params(r.blocks.begin(), r.blocks.end());
      if (!r.cost->Evaluate(params.data(), res, nullptr)) {
        (r.is_point ? r.frame->point_outlier : r.frame->segment_outlier)[r.observation] = 1;
        continue;
      }
    }
    const std::vector<const double*> first = FirstEstimatesOf(r.blocks);
    ceres::CostFunction* cost = r.cost.release();
    if (std::any_of(first.begin(), first.end(), [](const double* p) { return p != nullptr; })) {
      cost = new FirstEstimateCost(cost, first);
    }
    const ceres::ResidualBlockId id =
        problem->AddResidualBlock(cost, r.robust ? loss.get() : nullptr, r.blocks);
    if (observations && r.frame != nullptr) {
      observations->push_back({id, r.frame, r.observation, r.is_point});
    }
    ++n;
  }
  if (prior) {
    problem->AddResidualBlock(prior->CreateCostFunction(), nullptr, prior_blocks);
    ++n;
  }
  for (auto& f : keyframes) {
    if (problem->HasParameterBlock(f->pose)) problem->SetManifold(f->pose, &pose_manifold);
  }
  if (problem->HasParameterBlock(extrinsic)) problem->SetManifold(extrinsic, &pose_manifold);
  for (auto& rp : retained) {
    if (problem->HasParameterBlock(rp->pose)) problem->SetManifold(rp->pose, &pose_manifold);
  }
  for (auto& [id, l] : lines) {
    if (problem->HasParameterBlock(l->block)) problem->SetManifold(l->block, &line_manifold);
  }
  if (hold_gauge && !prior && !HasPosePrior() &&
      problem->HasParameterBlock(keyframes.front()->pose)) {
    if (opt.inertial && opt.inertial->free_first_tilt && keyframes.size() > 1) {
      problem->SetManifold(keyframes.front()->pose, &roll_pitch_manifold);
    } else {
      problem->SetParameterBlockConstant(keyframes.front()->pose);
      HoldStartScale(problem);
    }
  }
  return n;
}

// SlidingWindowOptions::start_scale_sigma: while the oldest keyframe holds the gauge, the
// distance of the second oldest to it is held at its value of the first solve with a third
// keyframe (the start's, as tracking moves neither), so that the scale is held too.
void SlidingWindowEstimator::Impl::HoldStartScale(ceres::Problem* problem) {
  if (!(opt.start_scale_sigma > 0.0) || opt.inertial || keyframes.size() < 3 ||
      !problem->HasParameterBlock(keyframes[1]->pose))
    return;
  const Eigen::Vector3d t0 = keyframes[0]->T_w_c().translation();
  if (!(start_distance > 0.0)) start_distance = (keyframes[1]->T_w_c().translation() - t0).norm();
  if (!(start_distance > 0.0) || !std::isfinite(start_distance)) return;
  problem->AddResidualBlock(
      new ceres::AutoDiffCostFunction<StartScaleResidual, 1, 7>(new StartScaleResidual{
          t0, start_distance, 1.0 / (opt.start_scale_sigma * start_distance)}),
      nullptr, keyframes[1]->pose);
}

ceres::Problem::Options SlidingWindowEstimator::Impl::ProblemOptions() {
  ceres::Problem::Options po;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  return po;
}

}  // namespace window
}  // namespace plucker
