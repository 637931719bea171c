// Online estimation of the camera-IMU time offset td (InertialOptions::estimate_time_offset;
// docs/math/time-offset.md): its block and prior, and the image velocities of the observations.
#include <ceres/autodiff_cost_function.h>

#include <stdexcept>

#include "plucker/window/window_factors_internal.h"
#include "plucker/window/window_internal.h"

namespace plucker {
namespace window {

void SlidingWindowEstimator::Impl::ResetTimeOffset() {
  time_offset[0] = opt.inertial ? opt.inertial->time_offset_s : 0.0;
  last_points.clear();
  last_segments.clear();
}

ceres::CostFunction* SlidingWindowEstimator::Impl::TimeOffsetPrior() const {
  return new ceres::AutoDiffCostFunction<internal::VectorPriorResidual<1>, 1, 1>(
      new internal::VectorPriorResidual<1>{
          Eigen::Matrix<double, 1, 1>(opt.inertial->time_offset_s),
          Eigen::Matrix<double, 1, 1>(1.0 / opt.inertial->time_offset_prior_sigma_s)});
}

// The velocity of an observation at frame k is first the difference of the track's two previous
// observations, (x_k-1 - x_k-2) / (t_k-1 - t_k-2) (zero without two): not the difference ending at
// x_k, whose noise is the observation's own and biases td towards the frame interval (an errors-
// in-variables bias: measured +11.6 ms on the MEMS room without any offset at 10 Hz, 1 px). It lags
// by 1.5 frames; a keyframe's is replaced by the central difference (x_k+1 - x_k-1) /
// (t_k+1 - t_k-1) when frame k+1 arrives (RefineNewestKeyframeVelocities), which does not lag and
// is still free of x_k's noise (room, +8 ms: 4.98 -> 5.62 ms recovered, +1.11 -> +0.28 ms without
// an offset; time_offset_estimation_test). A
// segment's endpoints are matched to the previous ones in the order that moves them least (a front
// end may swap them); their motion along the segment does not matter, only the normal component
// enters the residual.
void SlidingWindowEstimator::Impl::FillVelocities(Frame* frame) const {
  if (!TimeOffsetOn()) return;
  FrameInput* input = &frame->input;
  frame->point_velocity_filled.assign(input->points.size(), 0);
  frame->segment_velocity_filled.assign(input->segments.size(), 0);
  for (std::size_t i = 0; i < input->points.size(); ++i) {
    sensor::PointObservation& p = input->points[i];
    if (p.uv_velocity) continue;
    frame->point_velocity_filled[i] = 1;
    const auto it = last_points.find(p.point_id);
    p.uv_velocity = it == last_points.end() ? Eigen::Vector2d::Zero() : it->second.va;
  }
  for (std::size_t i = 0; i < input->segments.size(); ++i) {
    sensor::SegmentObservation& s = input->segments[i];
    if (s.s_velocity && s.e_velocity) continue;
    frame->segment_velocity_filled[i] = 1;
    const auto it = last_segments.find(s.line_id);
    if (it == last_segments.end()) {
      s.s_velocity = s.e_velocity = Eigen::Vector2d::Zero();
      continue;
    }
    const LastObservation& o = it->second;
    const bool swapped = Swapped(s.s_px, s.e_px, o);
    s.s_velocity = swapped ? o.vb : o.va;
    s.e_velocity = swapped ? o.va : o.vb;
  }
}

void SlidingWindowEstimator::Impl::RefineNewestKeyframeVelocities(const FrameInput& input) {
  if (!TimeOffsetOn() || keyframes.empty()) return;
  Frame& k = *keyframes.back();
  if (k.input.time >= input.time || k.point_velocity_filled.size() != k.input.points.size() ||
      k.segment_velocity_filled.size() != k.input.segments.size()) {
    return;
  }
  auto central = [&input](const Eigen::Vector2d& next, const LastObservation& o,
                          const Eigen::Vector2d& prev) {
    return Eigen::Vector2d((next - prev) / (input.time - o.prev_time));
  };
  std::map<int, const sensor::PointObservation*> next_points;
  for (const auto& p : input.points) next_points[p.point_id] = &p;
  for (std::size_t i = 0; i < k.input.points.size(); ++i) {
    sensor::PointObservation& p = k.input.points[i];
    const auto o = last_points.find(p.point_id);
    const auto n = next_points.find(p.point_id);
    if (!k.point_velocity_filled[i] || o == last_points.end() || n == next_points.end() ||
        o->second.time != k.input.time || !(o->second.prev_time < k.input.time)) {
      continue;
    }
    p.uv_velocity = central(n->second->uv, o->second, o->second.prev_a);
  }
  std::map<int, const sensor::SegmentObservation*> next_segments;
  for (const auto& s : input.segments) next_segments[s.line_id] = &s;
  for (std::size_t i = 0; i < k.input.segments.size(); ++i) {
    sensor::SegmentObservation& s = k.input.segments[i];
    const auto o = last_segments.find(s.line_id);
    const auto n = next_segments.find(s.line_id);
    if (!k.segment_velocity_filled[i] || o == last_segments.end() || n == next_segments.end() ||
        o->second.time != k.input.time || !(o->second.prev_time < k.input.time)) {
      continue;
    }
    // last.a, last.b are this keyframe's s, e (RememberObservations of its input); prev_a, prev_b
    // were matched to them.
    const LastObservation& last = o->second;
    const bool swapped = Swapped(n->second->s_px, n->second->e_px, last);
    const Eigen::Vector2d& next_a = swapped ? n->second->e_px : n->second->s_px;
    const Eigen::Vector2d& next_b = swapped ? n->second->s_px : n->second->e_px;
    s.s_velocity = central(next_a, last, last.prev_a);
    s.e_velocity = central(next_b, last, last.prev_b);
  }
}

bool SlidingWindowEstimator::Impl::Swapped(const Eigen::Vector2d& s, const Eigen::Vector2d& e,
                                           const LastObservation& o) {
  return (s - o.b).norm() + (e - o.a).norm() < (s - o.a).norm() + (e - o.b).norm();
}

void SlidingWindowEstimator::Impl::RememberObservations(const FrameInput& input) {
  if (!TimeOffsetOn()) return;
  const double t = input.time;
  // The difference velocity ending at this frame (zero without a previous observation).
  auto rate = [t](const Eigen::Vector2d& x, const Eigen::Vector2d& x_prev, double t_prev) {
    return t > t_prev ? Eigen::Vector2d((x - x_prev) / (t - t_prev)) : Eigen::Vector2d::Zero();
  };
  std::map<int, LastObservation> points_now, segments_now;
  for (const sensor::PointObservation& p : input.points) {
    const auto it = last_points.find(p.point_id);
    LastObservation o{t, p.uv, p.uv, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
    if (it != last_points.end()) {
      o.va = o.vb = rate(p.uv, it->second.a, it->second.time);
      o.prev_time = it->second.time;
      o.prev_a = o.prev_b = it->second.a;
    }
    points_now[p.point_id] = o;
  }
  for (const sensor::SegmentObservation& s : input.segments) {
    const auto it = last_segments.find(s.line_id);
    LastObservation o{t, s.s_px, s.e_px, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
    if (it != last_segments.end()) {
      const LastObservation& prev = it->second;
      const bool swapped = Swapped(s.s_px, s.e_px, prev);
      o.prev_time = prev.time;
      o.prev_a = swapped ? prev.b : prev.a;
      o.prev_b = swapped ? prev.a : prev.b;
      o.va = rate(s.s_px, o.prev_a, prev.time);
      o.vb = rate(s.e_px, o.prev_b, prev.time);
    }
    segments_now[s.line_id] = o;
  }
  last_points.swap(points_now);
  last_segments.swap(segments_now);
}

double SlidingWindowEstimator::TimeOffsetEstimate() const {
  if (!impl_->opt.inertial) throw std::logic_error("TimeOffsetEstimate: not in the inertial mode");
  return impl_->time_offset[0];
}

}  // namespace window
}  // namespace plucker
