// Decide: the keyframe policy (SlidingWindowOptions: parallax, tracked landmarks, rotation from and
// time since the newest keyframe; InertialOptions::max_imu_factor_span_s in the inertial mode).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "plucker/geometry/median.h"
#include "plucker/geometry/orthonormal_line.h"
#include "plucker/window/window_internal.h"

namespace plucker {
namespace window {

using internal::Frame;
using internal::TrackResult;

double SlidingWindowEstimator::Impl::Parallax(const Frame& f) const {
  const Frame& kf = *keyframes.back();
  std::unordered_map<int, Eigen::Vector2d> kf_uv;
  for (const auto& p : kf.input.points) kf_uv[p.point_id] = p.uv;
  const Eigen::Matrix3d R_c_kf =
      f.T_w_c().RotationMatrix().transpose() * kf.T_w_c().RotationMatrix();
  std::vector<double> d;
  for (const auto& p : f.input.points) {
    const auto it = kf_uv.find(p.point_id);
    if (it == kf_uv.end()) continue;
    const Eigen::Vector3d ray = R_c_kf * Eigen::Vector3d((it->second.x() - K.cx) / K.fx,
                                                         (it->second.y() - K.cy) / K.fy, 1.0);
    if (ray.z() <= 1e-6) continue;
    const Eigen::Vector2d uv(K.fx * ray.x() / ray.z() + K.cx, K.fy * ray.y() / ray.z() + K.cy);
    d.push_back((uv - p.uv).norm());
  }
  if (d.size() >= 8) return UpperMedian(d);
  // Too few common points (scarce points, many lines): the parallax the baseline to the newest
  // keyframe induces at the median depth of the tracked landmarks, f * baseline / depth.
  const SE3d T_c_w = f.T_w_c().Inverse();
  const Eigen::Vector3d centre = f.T_w_c().translation();
  std::vector<double> depth;
  for (std::size_t i = 0; i < f.input.points.size(); ++i) {
    const auto it = points.find(f.input.points[i].point_id);
    if (it == points.end() || f.point_outlier[i]) continue;
    const double z =
        (T_c_w * Eigen::Vector3d(it->second->p[0], it->second->p[1], it->second->p[2])).z();
    if (z > 0.0) depth.push_back(z);
  }
  for (std::size_t i = 0; i < f.input.segments.size(); ++i) {
    const auto it = lines.find(f.input.segments[i].line_id);
    if (it == lines.end() || f.segment_outlier[i]) continue;
    const Line6d L_w = WorldFromAnchored(
        PluckerFromOrthonormal(OrthonormalLine::FromParameters(it->second->block)),
        it->second->anchor);
    const std::optional<double> dist = PointLineDistance(L_w, centre);
    if (dist && *dist > 0.0) depth.push_back(*dist);
  }
  if (depth.empty()) return 0.0;
  const double baseline = (centre - kf.T_w_c().translation()).norm();
  return 0.5 * (K.fx + K.fy) * baseline / UpperMedian(depth);
}

// The frame's segments the tracked-ratio test counts (SlidingWindowOptions::
// tracked_ratio_mapped_segments): all, or those of mapped lines.
int SlidingWindowEstimator::Impl::TrackableSegments(const Frame& f) const {
  if (!opt.tracked_ratio_mapped_segments) return static_cast<int>(f.input.segments.size());
  int n = 0;
  for (const auto& s : f.input.segments) n += lines.count(s.line_id) > 0;
  return n;
}

namespace {
double AngleDeg(const SE3d& T_w_a, const SE3d& T_w_b) {
  return Eigen::AngleAxisd(T_w_a.RotationMatrix().transpose() * T_w_b.RotationMatrix()).angle() *
         180.0 / M_PI;
}
}  // namespace

// peak_turn_rate_deg_s with the turn from the previous frame to f.
void SlidingWindowEstimator::Impl::UpdateTurnRate(const Frame& f) {
  const double dt = f.input.time - last_time;
  if (dt > 0.0)
    peak_turn_rate_deg_s = std::max(peak_turn_rate_deg_s, AngleDeg(last_T_w_c, f.T_w_c()) / dt);
}

// The rotation keyframe (SlidingWindowOptions::keyframe_max_rotation_deg) when the frame has turned
// that much from the newest keyframe and, with keyframe_min_turn_rate_deg_s, some frame since that
// keyframe turned at that rate from its previous frame (the peak: the mean rate since the
// keyframe, or the rate of the frame alone, falls under the bound in the slow phases of a sway).
bool SlidingWindowEstimator::Impl::Turned(const Frame& f) const {
  return opt.keyframe_max_rotation_deg > 0.0 &&
         AngleDeg(keyframes.back()->T_w_c(), f.T_w_c()) >= opt.keyframe_max_rotation_deg &&
         peak_turn_rate_deg_s >= opt.keyframe_min_turn_rate_deg_s;
}

bool SlidingWindowEstimator::Impl::DecideKeyframe(const Frame& f, const TrackResult& track,
                                                  WindowFrameResult* result) const {
  result->parallax_px = Parallax(f);
  const int observed = static_cast<int>(f.input.points.size()) + TrackableSegments(f);
  const double since_keyframe = f.input.time - keyframes.back()->input.time;
  const bool turned = Turned(f);
  const bool keyframe =
      track.ok &&
      (result->parallax_px >= opt.keyframe_parallax_px || turned ||
       track.points + track.lines < opt.min_tracked ||
       track.points + track.lines < opt.min_tracked_ratio * observed ||
       (opt.max_keyframe_interval_s > 0.0 && since_keyframe >= opt.max_keyframe_interval_s));
  // Inertial mode: also when InertialOptions::max_imu_factor_span_s has passed, tracked or not
  // (the IMU factors stay short, a standing body keeps its window).
  // Untracked (no landmark yet, e.g. after a standing start, or all lost) but moved: a keyframe at
  // the IMU's pose as soon as the image shows parallax, so that vision starts (triangulates)
  // without waiting for max_imu_factor_span_s of IMU-only frames.
  const bool untracked_parallax = !track.ok && result->parallax_px >= opt.keyframe_parallax_px;
  if (opt.inertial)
    return keyframe || untracked_parallax || since_keyframe >= opt.inertial->max_imu_factor_span_s;
  return keyframe;
}

}  // namespace window
}  // namespace plucker
