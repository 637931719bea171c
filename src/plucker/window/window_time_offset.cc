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

// The velocity of an observation at frame k is the difference of the track's two previous
// observations, (x_k-1 - x_k-2) / (t_k-1 - t_k-2) (zero without two): not the difference ending at
// x_k, whose noise is the observation's own and biases td towards the frame interval (an errors-
// in-variables bias: measured +11.6 ms on the MEMS room without any offset at 10 Hz, 1 px). A
// segment's endpoints are matched to the previous ones in the order that moves them least (a front
// end may swap them); their motion along the segment does not matter, only the normal component
// enters the residual.
void SlidingWindowEstimator::Impl::FillVelocities(FrameInput* input) const {
  if (!TimeOffsetOn()) return;
  for (sensor::PointObservation& p : input->points) {
    if (p.uv_velocity) continue;
    const auto it = last_points.find(p.point_id);
    p.uv_velocity = it == last_points.end() ? Eigen::Vector2d::Zero() : it->second.va;
  }
  for (sensor::SegmentObservation& s : input->segments) {
    if (s.s_velocity && s.e_velocity) continue;
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
    if (it != last_points.end()) o.va = o.vb = rate(p.uv, it->second.a, it->second.time);
    points_now[p.point_id] = o;
  }
  for (const sensor::SegmentObservation& s : input.segments) {
    const auto it = last_segments.find(s.line_id);
    LastObservation o{t, s.s_px, s.e_px, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
    if (it != last_segments.end()) {
      const LastObservation& prev = it->second;
      const bool swapped = Swapped(s.s_px, s.e_px, prev);
      o.va = rate(s.s_px, swapped ? prev.b : prev.a, prev.time);
      o.vb = rate(s.e_px, swapped ? prev.a : prev.b, prev.time);
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
