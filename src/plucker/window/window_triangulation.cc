// New points and lines for the newest keyframe's tracks from the window's keyframes (linear
// N-view triangulation with the parallax and conditioning checks of the options).
#include <algorithm>
#include <cmath>

#include "plucker/geometry/orthonormal_line.h"
#include "plucker/window/window_internal.h"

namespace plucker {
namespace window {

using internal::Frame;
using internal::LineLandmark;
using internal::PointLandmark;

// Whether the RMS endpoint-to-line distance of L_w in `views` is at most max_new_line_rms_px.
bool SlidingWindowEstimator::Impl::LineFits(const std::vector<LineObservation>& views,
                                            const Line6d& L_w) const {
  const std::optional<Eigen::VectorXd> e = LineReprojectionErrors(K, views, L_w);
  if (!e || e->size() == 0) return false;
  return std::sqrt(e->squaredNorm() / static_cast<double>(e->size())) <= opt.max_new_line_rms_px;
}

// The new keyframe `f`'s inlier observations of existing lines: one more view each. With
// SlidingWindowOptions::recheck_two_view_lines, a line made from two views that `f` sees for the
// third time is triangulated again from its views with the new-line checks: replaced by that
// estimate, or dropped when a check fails (not when it is in the prior).
void SlidingWindowEstimator::Impl::CountLineViews(const Frame& f, WindowFrameResult* stats) {
  for (std::size_t i = 0; i < f.input.segments.size(); ++i) {
    const int id = f.input.segments[i].line_id;
    const auto it = lines.find(id);
    if (it == lines.end() || f.segment_outlier[i]) continue;
    if (++it->second->views != 3 || !opt.recheck_two_view_lines || InPrior(it->second->block))
      continue;
    std::unique_ptr<LineLandmark> lm = NewLine(id, 3, stats);
    if (lm) {
      it->second = std::move(lm);
    } else {
      lines.erase(it);
      ++stats->rechecked_lines_dropped;
    }
  }
}

// New landmarks for the tracks of keyframe `f` (the newest) that have none yet.
void SlidingWindowEstimator::Impl::Triangulate(const Frame& f, int* new_points, int* new_lines,
                                               WindowFrameResult* stats) {
  WindowFrameResult unused;
  WindowFrameResult& st = stats ? *stats : unused;
  for (const auto& obs : f.input.points) {
    if (points.count(obs.point_id) || retired_points.count(obs.point_id)) continue;
    std::vector<SE3d> poses;
    std::vector<Eigen::Vector2d> uvs;
    for (const auto& kf : keyframes) {
      for (std::size_t i = 0; i < kf->input.points.size(); ++i) {
        if (kf->input.points[i].point_id != obs.point_id || kf->point_outlier[i]) continue;
        poses.push_back(kf->T_w_c());
        uvs.push_back(kf->input.points[i].uv);
        if (kf->right_point.size() > i && kf->right_point[i] >= 0) {  // stereo
          poses.push_back(RightPose(*kf));
          uvs.push_back(kf->input.right_points[kf->right_point[i]].uv);
        }
        break;
      }
    }
    if (poses.size() < 2) continue;
    const PointTriangulationResult t = TriangulatePoint(K, poses, uvs, opt.point_triangulation);
    if (!t.ok() || t.final_rms_px > 2.0 * opt.point_sigma_px + 1.0) continue;
    auto lm = std::make_unique<PointLandmark>();
    for (int i = 0; i < 3; ++i) lm->p[i] = t.p_w(i);
    points[obs.point_id] = std::move(lm);
    ++*new_points;
  }
  if (!opt.use_lines) return;
  for (const auto& obs : f.input.segments) {
    if (lines.count(obs.line_id) || retired_lines.count(obs.line_id)) continue;
    std::unique_ptr<LineLandmark> lm = NewLine(obs.line_id, opt.min_line_views, &st);
    if (!lm) continue;
    lines[obs.line_id] = std::move(lm);
    ++*new_lines;
  }
}

// The inlier views of line track `id` in the window's keyframes (and their right cameras).
std::vector<LineObservation> SlidingWindowEstimator::Impl::LineViews(int id) const {
  std::vector<LineObservation> views;
  for (const auto& kf : keyframes) {
    for (std::size_t i = 0; i < kf->input.segments.size(); ++i) {
      const auto& s = kf->input.segments[i];
      if (s.line_id != id || kf->segment_outlier[i]) continue;
      views.push_back({kf->T_w_c(), s.s_px, s.e_px});
      if (kf->right_segment.size() > i && kf->right_segment[i] >= 0) {  // stereo
        const auto& rs = kf->input.right_segments[kf->right_segment[i]];
        views.push_back({RightPose(*kf), rs.s_px, rs.e_px});
      }
      break;
    }
  }
  return views;
}

// A line for track `id` from at least `min_views` views with the checks of the options (nullptr
// when there are fewer or a check fails); counts the tries and rejections into `st`.
std::unique_ptr<LineLandmark> SlidingWindowEstimator::Impl::NewLine(
    int id, int min_views, WindowFrameResult* stats) const {
  WindowFrameResult& st = *stats;
  const std::vector<LineObservation> views = LineViews(id);
  if (views.size() < static_cast<std::size_t>(std::max(min_views, 2))) return nullptr;
  ++st.line_candidates;
  LineTriangulationOptions to = opt.line_triangulation;
  if (views.size() == 2 && opt.two_view_min_plane_angle_px > 0.0) {
    const double pixel_angle_deg =
        std::atan(opt.two_view_min_plane_angle_px / (0.5 * (K.fx + K.fy))) * 180.0 / M_PI;
    to.min_plane_angle_deg = std::max(to.min_plane_angle_deg, pixel_angle_deg);
  }
  const LineTriangulationResult t = TriangulateLine(K, views, to);
  if (t.status == LineTriangulationStatus::kSmallParallax) ++st.line_small_parallax;
  const bool ill = t.status == LineTriangulationStatus::kIllConditioned ||
                   (t.ok() && t.sigma_ratio > opt.max_line_sigma_ratio);
  st.line_ill_conditioned += ill;
  if (!t.ok() && !ill && t.status != LineTriangulationStatus::kSmallParallax)
    ++st.line_other_rejections;
  if (!t.ok() || t.sigma_ratio > opt.max_line_sigma_ratio) return nullptr;
  if (opt.max_new_line_rms_px > 0.0 && !LineFits(views, t.L_w)) {
    ++st.line_other_rejections;
    return nullptr;
  }
  LineAnchor anchor;
  if (opt.condition_far_lines) anchor = MakeLineAnchor(t.L_w, views.front().T_w_c.translation());
  const std::optional<OrthonormalLine> o = OrthonormalFromPlucker(AnchoredFromWorld(t.L_w, anchor));
  if (!o) return nullptr;
  auto lm = std::make_unique<LineLandmark>();
  lm->anchor = anchor;
  lm->views = static_cast<int>(views.size());
  o->ToParameters(lm->block);
  return lm;
}

}  // namespace window
}  // namespace plucker
