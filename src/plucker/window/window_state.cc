// The window's bookkeeping: frames made from the caller's input, the blocks of the state and
// their kinds, weak landmarks and retained poses removed, a new marginalization prior installed
// and the oldest keyframe dropped (the shared tail of both marginalization strategies).
#include <algorithm>
#include <cmath>

#include "plucker/window/window_internal.h"

namespace plucker {
namespace window {

using internal::BlockKind;
using internal::Frame;
using internal::RetainedPose;

namespace {

bool ValidSegment(const sensor::SegmentObservation& s) {
  return s.line_id >= 0 && s.s_px.allFinite() && s.e_px.allFinite() &&
         (s.e_px - s.s_px).norm() >= 1.0;
}

bool ValidPoint(const sensor::PointObservation& p) { return p.point_id >= 0 && p.uv.allFinite(); }

}  // namespace

std::unique_ptr<Frame> SlidingWindowEstimator::Impl::MakeFrame(const FrameInput& input,
                                                               const SE3d& T_w_c) const {
  auto f = std::make_unique<Frame>();
  f->input.time = input.time;
  f->input.T_w_c_prior = input.T_w_c_prior;
  f->input.prior_sqrt_information = input.prior_sqrt_information;
  f->input.stationary = input.stationary;
  for (const auto& p : input.points)
    if (ValidPoint(p)) f->input.points.push_back(p);
  if (opt.use_lines) {
    for (const auto& s : input.segments)
      if (ValidSegment(s)) f->input.segments.push_back(s);
  }
  f->point_outlier.assign(f->input.points.size(), 0);
  f->segment_outlier.assign(f->input.segments.size(), 0);
  AttachRight(f.get(), input);
  FillVelocities(f.get());
  if (TimeOffsetOn()) f->gyro = GyroAt(input.time);
  if (opt.inertial) f->T_b_c = T_b_c;
  f->SetCameraPose(T_w_c);
  return f;
}

void SlidingWindowEstimator::Impl::Clear() {
  keyframes.clear();
  points.clear();
  lines.clear();
  prior.reset();
  prior_blocks.clear();
  fe.clear();
  retired_points.clear();
  retired_lines.clear();
  retained.clear();
  ResetExtrinsic();
  ResetTimeOffset();
  prior_lines = 0;
}

bool SlidingWindowEstimator::Impl::InPrior(const double* block) const {
  return std::find(prior_blocks.begin(), prior_blocks.end(), block) != prior_blocks.end();
}

BlockKind SlidingWindowEstimator::Impl::KindOf(const double* block) const {
  if (block == extrinsic) return BlockKind::kPose;
  if (block == time_offset) return BlockKind::kTimeOffset;
  for (const auto& rp : retained)
    if (rp->pose == block) return BlockKind::kPose;
  for (const auto& f : keyframes) {
    if (f->pose == block) return BlockKind::kPose;
    if (f->v == block) return BlockKind::kVelocity;
    if (f->bias == block) return BlockKind::kBias;
  }
  for (const auto& [id, l] : lines)
    if (l->block == block) return BlockKind::kLine;
  return BlockKind::kPoint;
}

const ceres::Manifold* SlidingWindowEstimator::Impl::ManifoldOf(BlockKind kind) const {
  if (kind == BlockKind::kPose) return &pose_manifold;
  if (kind == BlockKind::kLine) return &line_manifold;
  return nullptr;
}

int SlidingWindowEstimator::Impl::AmbientSize(BlockKind kind) {
  if (kind == BlockKind::kBias) return 6;
  if (kind == BlockKind::kTimeOffset) return 1;
  return kind == BlockKind::kPose ? 7 : (kind == BlockKind::kLine ? 6 : 3);
}

// Landmarks observed (as inliers) by fewer than two keyframes and not in the prior.
void SlidingWindowEstimator::Impl::RemoveWeakLandmarks() {
  std::map<int, int> point_count, line_count;
  for (const auto& f : keyframes) {
    for (std::size_t i = 0; i < f->input.points.size(); ++i)
      if (!f->point_outlier[i]) ++point_count[f->input.points[i].point_id];
    for (std::size_t i = 0; i < f->input.segments.size(); ++i)
      if (!f->segment_outlier[i]) ++line_count[f->input.segments[i].line_id];
    // Stereo: the right observation of an inlier is a second view.
    for (std::size_t i = 0; i < f->right_point.size(); ++i)
      if (f->right_point[i] >= 0 && !f->point_outlier[i])
        ++point_count[f->input.points[i].point_id];
    for (std::size_t i = 0; i < f->right_segment.size(); ++i)
      if (f->right_segment[i] >= 0 && !f->segment_outlier[i])
        ++line_count[f->input.segments[i].line_id];
  }
  for (const auto& rp : retained)
    for (const auto& seg : rp->segments) ++line_count[seg.line_id];
  for (auto it = points.begin(); it != points.end();) {
    if (point_count[it->first] < 2 && !InPrior(it->second->p)) {
      it = points.erase(it);
    } else {
      ++it;
    }
  }
  for (auto it = lines.begin(); it != lines.end();) {
    if (line_count[it->first] < 2 && !InPrior(it->second->block)) {
      it = lines.erase(it);
    } else {
      ++it;
    }
  }
  PruneRetained(false);
}

// Drops the retained observations whose line is gone (or, with `cull`, whose residual exceeds
// the outlier threshold), then the retained poses left with none that are not in the prior
// (those in it leave at the next marginalization). Returns the observations culled.
int SlidingWindowEstimator::Impl::PruneRetained(bool cull) {
  int culled = 0;
  for (auto& rp : retained) {
    std::vector<sensor::SegmentObservation> keep;
    for (const sensor::SegmentObservation& seg : rp->segments) {
      const auto it = lines.find(seg.line_id);
      if (it == lines.end()) continue;
      if (cull) {
        std::unique_ptr<ceres::CostFunction> cost(LineCost(seg, *it->second));
        double res[2];
        const double* params[2] = {rp->pose, it->second->block};
        if (!cost->Evaluate(params, res, nullptr) || !std::isfinite(res[0]) ||
            !std::isfinite(res[1]) || std::hypot(res[0], res[1]) > opt.outlier_sigmas) {
          ++culled;
          continue;
        }
      }
      keep.push_back(seg);
    }
    rp->segments.swap(keep);
  }
  retained.erase(std::remove_if(retained.begin(), retained.end(),
                                [this](const std::unique_ptr<RetainedPose>& rp) {
                                  return rp->segments.empty() && !InPrior(rp->pose);
                                }),
                 retained.end());
  return culled;
}

// The new prior and its first estimates (none if empty).
void SlidingWindowEstimator::Impl::InstallPrior(std::unique_ptr<MarginalizationPrior> next,
                                                const std::vector<double*>& next_blocks,
                                                WindowFrameResult* result) {
  fe.clear();
  prior = std::move(next);
  prior_blocks = next_blocks;
  prior_lines = 0;
  if (!prior) return;
  result->prior_rank = prior->Statistics().prior_rank;
  result->prior_dimension = prior->Statistics().kept_dimension;
  for (std::size_t i = 0; i < prior_blocks.size(); ++i) {
    const BlockKind kind = KindOf(prior_blocks[i]);
    if (opt.first_estimate_landmarks || (kind != BlockKind::kPoint && kind != BlockKind::kLine))
      fe[prior_blocks[i]] = prior->LinearisationPoint()[i];
  }
  if (prior->Statistics().prior_rank == 0) {
    prior.reset();
    prior_blocks.clear();
    fe.clear();
  }
  prior_lines = static_cast<int>(
      std::count_if(prior_blocks.begin(), prior_blocks.end(),
                    [this](const double* b) { return KindOf(b) == BlockKind::kLine; }));
}

// After k0 went into the prior: drop it and the landmarks eliminated with it.
void SlidingWindowEstimator::Impl::DropOldestKeyframe(const std::vector<int>& remove_points,
                                                      const std::vector<int>& remove_lines,
                                                      WindowFrameResult* result) {
  keyframes.pop_front();
  keyframes.front()->imu_from_previous.reset();
  keyframes.front()->state_prior = false;
  for (int id : remove_points) points.erase(id);
  for (int id : remove_lines) lines.erase(id);
  result->marginalized_keyframes = 1;
  result->marginalized_landmarks = static_cast<int>(remove_points.size() + remove_lines.size());
  RemoveWeakLandmarks();
}

}  // namespace window
}  // namespace plucker
