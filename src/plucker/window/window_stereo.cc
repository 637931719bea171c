// Stereo mode (SlidingWindowOptions::T_c0_c1): the second camera's observations attached to a
// frame, their residuals (the verified VI factors with the extrinsic held at T_c0_c1: no new
// factor), and the one-keyframe start from the left-right pairs.
#include <map>
#include <stdexcept>

#include "plucker/factors/held_extrinsic_factor.h"
#include "plucker/factors/point_reprojection_factor.h"
#include "plucker/window/window_internal.h"

namespace plucker {
namespace window {

using internal::Frame;
using internal::ResidualSpec;

void SlidingWindowEstimator::Impl::AttachRight(Frame* f, const FrameInput& input) const {
  f->right_point.assign(f->input.points.size(), -1);
  f->right_segment.assign(f->input.segments.size(), -1);
  if (!opt.T_c0_c1) return;
  std::map<int, int> left_point, left_segment;  // track id -> left index
  for (std::size_t i = 0; i < f->input.points.size(); ++i)
    left_point.emplace(f->input.points[i].point_id, static_cast<int>(i));
  for (std::size_t i = 0; i < f->input.segments.size(); ++i)
    left_segment.emplace(f->input.segments[i].line_id, static_cast<int>(i));
  for (const sensor::PointObservation& p : input.right_points) {
    const auto it = left_point.find(p.point_id);
    if (p.point_id < 0 || !p.uv.allFinite() || it == left_point.end() ||
        f->right_point[it->second] >= 0)
      continue;
    f->right_point[it->second] = static_cast<int>(f->input.right_points.size());
    f->input.right_points.push_back(p);
  }
  if (!opt.use_lines) return;
  for (const sensor::SegmentObservation& s : input.right_segments) {
    const auto it = left_segment.find(s.line_id);
    if (s.line_id < 0 || !s.s_px.allFinite() || !s.e_px.allFinite() ||
        (s.e_px - s.s_px).norm() < 1.0 || it == left_segment.end() ||
        f->right_segment[it->second] >= 0)
      continue;
    f->right_segment[it->second] = static_cast<int>(f->input.right_segments.size());
    f->input.right_segments.push_back(s);
  }
}

void SlidingWindowEstimator::Impl::AppendRightResiduals(Frame* f, bool with_points, bool with_lines,
                                                        std::vector<ResidualSpec>* out) const {
  if (!opt.T_c0_c1) return;
  const SE3d& T_c0_c1 = *opt.T_c0_c1;
  if (with_points) {
    for (std::size_t i = 0; i < f->right_point.size(); ++i) {
      if (f->right_point[i] < 0 || f->point_outlier[i]) continue;
      const auto it = points.find(f->input.points[i].point_id);
      if (it == points.end()) continue;
      const sensor::PointObservation& p = f->input.right_points[f->right_point[i]];
      ResidualSpec r;
      r.cost.reset(new HeldExtrinsicFactor<3>(
          PointReprojectionFactorVI::Create(K, p.uv, PointSqrtInfo(p)), T_c0_c1));
      r.blocks = std::vector<double*>{f->pose, it->second->p};
      r.frame = f;
      r.observation = static_cast<int>(i);
      r.right = true;
      out->push_back(std::move(r));
    }
  }
  if (with_lines) {
    for (std::size_t i = 0; i < f->right_segment.size(); ++i) {
      if (f->right_segment[i] < 0 || f->segment_outlier[i]) continue;
      const auto it = lines.find(f->input.segments[i].line_id);
      if (it == lines.end()) continue;
      const sensor::SegmentObservation& s = f->input.right_segments[f->right_segment[i]];
      ResidualSpec r;
      r.cost.reset(new HeldExtrinsicFactor<6>(
          AnchoredLineFactorVI::Create(K, s.s_px, s.e_px, LineSqrtInfo(*it->second),
                                       it->second->anchor),
          T_c0_c1));
      r.blocks = std::vector<double*>{f->pose, it->second->block};
      r.frame = f;
      r.observation = static_cast<int>(i);
      r.is_point = false;
      r.right = true;
      out->push_back(std::move(r));
    }
  }
}

InitializationResult SlidingWindowEstimator::InitializeStereo(const FrameInput& frame,
                                                              const SE3d& T_w_c,
                                                              int min_landmarks) {
  Impl& m = *impl_;
  if (!m.opt.T_c0_c1) throw std::logic_error("InitializeStereo: not in the stereo mode");
  m.Clear();
  m.keyframes.push_back(m.MakeFrame(frame, T_w_c));
  return m.StartWindow(min_landmarks);
}

}  // namespace window
}  // namespace plucker
