// Online estimation of the camera-IMU time offset td (InertialOptions::estimate_time_offset;
// docs/math/time-offset.md): its block and prior, and the image velocities of the observations.
#include <ceres/autodiff_cost_function.h>

#include <cmath>
#include <stdexcept>

#include "plucker/factors/anchored_line_factor.h"
#include "plucker/geometry/orthonormal_line.h"
#include "plucker/window/window_factors_internal.h"
#include "plucker/window/window_internal.h"

namespace plucker {
namespace window {
namespace {

// The motion of a camera on the body: state (T_w_b, v_w), angular rate omega_b (body frame).
struct CameraMotion {
  SE3d T_w_c;
  Eigen::Vector3d omega_c;  // angular rate, camera frame
  Eigen::Vector3d c_dot_w;  // velocity of the camera centre, world frame
};

CameraMotion MotionOf(const SE3d& T_w_b, const Eigen::Vector3d& v_w, const Eigen::Vector3d& omega_b,
                      const SE3d& T_b_c) {
  const Eigen::Matrix3d R_w_b = T_w_b.RotationMatrix();
  return {T_w_b * T_b_c, T_b_c.RotationMatrix().transpose() * omega_b,
          v_w + R_w_b * omega_b.cross(T_b_c.translation())};
}

// d/dt pi(K, T_c_w(t) x_w) [px/s]: p_c = R_w_c^T (x_w - c_w), dp_c/dt = -omega_c x p_c -
// R_w_c^T dc_w/dt. None behind (or nearly at) the camera.
std::optional<Eigen::Vector2d> ImageVelocity(const PinholeIntrinsics& K, const CameraMotion& m,
                                             const Eigen::Vector3d& x_w) {
  const Eigen::Vector3d p_c = m.T_w_c.Inverse() * x_w;
  if (!(p_c.z() > 1e-3)) return std::nullopt;
  const Eigen::Vector3d dp_c =
      -m.omega_c.cross(p_c) - m.T_w_c.RotationMatrix().transpose() * m.c_dot_w;
  const double z2 = p_c.z() * p_c.z();
  const Eigen::Vector2d v(K.fx * (dp_c.x() * p_c.z() - p_c.x() * dp_c.z()) / z2,
                          K.fy * (dp_c.y() * p_c.z() - p_c.y() * dp_c.z()) / z2);
  if (!v.allFinite()) return std::nullopt;
  return v;
}

// The point of the world line L_w nearest to the ray of pixel uv from the camera T_w_c (none for
// a ray parallel to the line or a degenerate line).
std::optional<Eigen::Vector3d> LinePointOfRay(const PinholeIntrinsics& K, const SE3d& T_w_c,
                                              const Line6d& L_w, const Eigen::Vector2d& uv) {
  const Eigen::Vector3d n = L_w.head<3>(), d = L_w.tail<3>();
  const double dn = d.norm();
  if (!(dn > 0.0)) return std::nullopt;
  const Eigen::Vector3d u = d / dn;
  const Eigen::Vector3d a0 = d.cross(n) / (dn * dn);  // nearest to the origin
  const Eigen::Vector3d c = T_w_c.translation();
  const Eigen::Vector3d w = (T_w_c.RotationMatrix() *
                             Eigen::Vector3d((uv.x() - K.cx) / K.fx, (uv.y() - K.cy) / K.fy, 1.0))
                                .normalized();
  const Eigen::Vector3d r = a0 - c;
  const double b = u.dot(w), denom = 1.0 - b * b;
  if (!(denom > 1e-6)) return std::nullopt;
  const double s = (b * w.dot(r) - u.dot(r)) / denom;
  const Eigen::Vector3d x = a0 + s * u;
  if (!x.allFinite()) return std::nullopt;
  return x;
}

}  // namespace

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

std::optional<Eigen::Vector3d> SlidingWindowEstimator::Impl::GyroAt(double t) const {
  for (std::size_t i = 1; i < imu.size(); ++i) {
    if (imu[i].t < t) continue;
    const sensor::ImuSample &a = imu[i - 1], &b = imu[i];
    if (!(a.t <= t) || !(b.t > a.t)) return std::nullopt;
    const double w = (t - a.t) / (b.t - a.t);
    return Eigen::Vector3d((1.0 - w) * a.gyro + w * b.gyro);
  }
  return std::nullopt;
}

// Each keyframe with a gyroscope reading: its filled-in velocities of points and segments whose
// landmark is in the window, predicted from the current state (held during the solve, as the
// differenced ones; the Jacobians of the velocity on the state, of order td, are left out).
// Observations whose prediction fails keep their differenced velocity.
void SlidingWindowEstimator::Impl::PredictImageVelocities() {
  if (!TimeOffsetOn() || !opt.inertial->time_offset_velocity_from_state) return;
  for (auto& fp : keyframes) {
    Frame& f = *fp;
    if (!f.gyro || f.point_velocity_filled.size() != f.input.points.size() ||
        f.segment_velocity_filled.size() != f.input.segments.size()) {
      continue;
    }
    const Eigen::Vector3d omega_b = *f.gyro - Eigen::Vector3d(f.bias[0], f.bias[1], f.bias[2]);
    const CameraMotion m =
        MotionOf(SE3d::FromParameters(f.pose), Eigen::Vector3d(f.v[0], f.v[1], f.v[2]), omega_b,
                 f.T_b_c.value_or(T_b_c));
    for (std::size_t i = 0; i < f.input.points.size(); ++i) {
      sensor::PointObservation& p = f.input.points[i];
      const auto it = points.find(p.point_id);
      if (!f.point_velocity_filled[i] || it == points.end()) continue;
      const auto v = ImageVelocity(
          K, m, Eigen::Vector3d(it->second->p[0], it->second->p[1], it->second->p[2]));
      if (v) p.uv_velocity = *v;
    }
    for (std::size_t i = 0; i < f.input.segments.size(); ++i) {
      sensor::SegmentObservation& s = f.input.segments[i];
      const auto it = lines.find(s.line_id);
      if (!f.segment_velocity_filled[i] || it == lines.end()) continue;
      const Line6d L_w = WorldFromAnchored(
          PluckerFromOrthonormal(OrthonormalLine::FromParameters(it->second->block)),
          it->second->anchor);
      const auto xs = LinePointOfRay(K, m.T_w_c, L_w, s.s_px);
      const auto xe = LinePointOfRay(K, m.T_w_c, L_w, s.e_px);
      if (!xs || !xe) continue;
      const auto vs = ImageVelocity(K, m, *xs), ve = ImageVelocity(K, m, *xe);
      if (!vs || !ve) continue;
      s.s_velocity = *vs;
      s.e_velocity = *ve;
    }
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
