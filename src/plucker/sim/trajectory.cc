#include "plucker/sim/trajectory.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace plucker {
namespace sim {

using Eigen::Matrix3d;
using Eigen::Vector3d;

double SmoothSignal::Value(double t) const {
  double v = offset + rate * t;
  for (const Sinusoid& s : terms) v += s.amplitude * std::sin(s.omega * t + s.phase);
  return v;
}

double SmoothSignal::FirstDerivative(double t) const {
  double v = rate;
  for (const Sinusoid& s : terms) v += s.amplitude * s.omega * std::cos(s.omega * t + s.phase);
  return v;
}

double SmoothSignal::SecondDerivative(double t) const {
  double v = 0.0;
  for (const Sinusoid& s : terms) {
    v -= s.amplitude * s.omega * s.omega * std::sin(s.omega * t + s.phase);
  }
  return v;
}

Trajectory::Trajectory(const std::array<SmoothSignal, 3>& position_w, const SmoothSignal& yaw,
                       const SmoothSignal& pitch, const SmoothSignal& roll, double duration)
    : position_w_(position_w), yaw_(yaw), pitch_(pitch), roll_(roll), duration_(duration) {}

void Trajectory::SetStandingStart(double stand_s, double ramp_s) {
  if (!std::isfinite(stand_s) || !std::isfinite(ramp_s) || stand_s < 0.0 || ramp_s < 0.0) {
    throw std::invalid_argument("Trajectory::SetStandingStart: negative or non-finite times");
  }
  stand_s_ = stand_s;
  ramp_s_ = stand_s > 0.0 ? ramp_s : 0.0;
}

// u' = smoothstep(x) = 3x^2 - 2x^3 over the ramp (x = (t - stand) / ramp), so u = ramp (x^3 -
// x^4 / 2) and u'' = 6 (x - x^2) / ramp; after the ramp u = t - stand - ramp / 2.
Trajectory::Warp Trajectory::WarpAt(double t) const {
  if (stand_s_ <= 0.0) return {t, 1.0, 0.0};
  if (t <= stand_s_) return {0.0, 0.0, 0.0};
  if (ramp_s_ <= 0.0) return {t - stand_s_, 1.0, 0.0};  // a step in velocity
  const double x = (t - stand_s_) / ramp_s_;
  if (x >= 1.0) return {t - stand_s_ - 0.5 * ramp_s_, 1.0, 0.0};
  const double x2 = x * x, x3 = x2 * x;
  return {ramp_s_ * (x3 - 0.5 * x2 * x2), 3.0 * x2 - 2.0 * x3, 6.0 * (x - x2) / ramp_s_};
}

Matrix3d Trajectory::R_w_b(double t) const {
  const double u = WarpAt(t).u;
  return (Eigen::AngleAxisd(yaw_.Value(u), Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch_.Value(u), Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll_.Value(u), Vector3d::UnitX()))
      .toRotationMatrix();
}

SE3d Trajectory::T_w_b(double t) const { return SE3d(R_w_b(t), position_w(t)); }

Vector3d Trajectory::position_w(double t) const {
  const double u = WarpAt(t).u;
  return Vector3d(position_w_[0].Value(u), position_w_[1].Value(u), position_w_[2].Value(u));
}

Vector3d Trajectory::velocity_w(double t) const {
  const Warp w = WarpAt(t);
  return w.du * Vector3d(position_w_[0].FirstDerivative(w.u), position_w_[1].FirstDerivative(w.u),
                         position_w_[2].FirstDerivative(w.u));
}

// d2/dt2 p(u(t)) = p''(u) u'^2 + p'(u) u''.
Vector3d Trajectory::acceleration_w(double t) const {
  const Warp w = WarpAt(t);
  Vector3d a;
  for (int i = 0; i < 3; ++i) {
    a(i) = position_w_[i].SecondDerivative(w.u) * w.du * w.du +
           position_w_[i].FirstDerivative(w.u) * w.ddu;
  }
  return a;
}

// R = Rz(yaw) Ry(pitch) Rx(roll)  =>  R^T R' = [omega_b]x with
// omega_b = roll' e_x + pitch' Rx^T e_y + yaw' Rx^T Ry^T e_z (rates in t: u' times those in u).
Vector3d Trajectory::angular_velocity_b(double t) const {
  const Warp w = WarpAt(t);
  const double pitch = pitch_.Value(w.u), roll = roll_.Value(w.u);
  const double dyaw = w.du * yaw_.FirstDerivative(w.u), dpitch = w.du * pitch_.FirstDerivative(w.u),
               droll = w.du * roll_.FirstDerivative(w.u);
  const double sp = std::sin(pitch), cp = std::cos(pitch), sr = std::sin(roll), cr = std::cos(roll);
  return Vector3d(droll - dyaw * sp, dpitch * cr + dyaw * cp * sr, -dpitch * sr + dyaw * cp * cr);
}

Vector3d Trajectory::angular_velocity_w(double t) const { return R_w_b(t) * angular_velocity_b(t); }

Vector3d Trajectory::euler_zyx(double t) const {
  const double u = WarpAt(t).u;
  return Vector3d(yaw_.Value(u), pitch_.Value(u), roll_.Value(u));
}

namespace {

constexpr double kPi = 3.14159265358979323846;

void CheckFinite(double v, bool positive, const char* name) {
  if (!std::isfinite(v) || v < 0.0 || (positive && v == 0.0)) {
    throw std::invalid_argument(std::string("MakeTrajectory: invalid ") + name);
  }
}

}  // namespace

Trajectory MakeTrajectory(const TrajectoryOptions& options, const Scene& scene,
                          std::uint64_t seed) {
  CheckFinite(options.duration, false, "duration");
  CheckFinite(options.speed, true, "speed");
  CheckFinite(options.eye_height, false, "eye_height");
  CheckFinite(options.yaw_sway, false, "yaw_sway");
  CheckFinite(options.pitch_amplitude, false, "pitch_amplitude");
  CheckFinite(options.roll_amplitude, false, "roll_amplitude");
  CheckFinite(options.wobble, false, "wobble");
  CheckFinite(options.standing_start_s, false, "standing_start_s");
  CheckFinite(options.start_ramp_s, false, "start_ramp_s");
  CheckFinite(options.turn_frequency_scale, true, "turn_frequency_scale");
  if (options.pitch_amplitude > 0.5 || options.roll_amplitude > 0.5) {
    throw std::invalid_argument("MakeTrajectory: pitch/roll amplitudes above 0.5 rad");
  }
  const Eigen::AlignedBox3d& box = scene.free_space_w;
  if (box.isEmpty() || !box.min().allFinite() || !box.max().allFinite()) {
    throw std::invalid_argument("MakeTrajectory: the scene has no free space");
  }
  std::mt19937_64 rng(seed);
  auto phase = [&rng] { return std::uniform_real_distribution<double>(0.0, 2.0 * kPi)(rng); };

  const Vector3d center = box.center();
  const Vector3d half = 0.5 * box.sizes();
  // Position wobble (IMU excitation) at fixed frequencies, limited to a quarter of the room.
  const Vector3d wobble = half.cwiseMin(options.wobble * 4.0) * 0.25;
  const Vector3d reach = half - 2.0 * wobble;  // what the main motion may use
  std::array<SmoothSignal, 3> p;
  const double wobble_omega[3] = {2 * kPi * 0.7, 2 * kPi * 0.9, 2 * kPi * 1.1};
  for (int i = 0; i < 3; ++i) p[i].offset = center(i);

  // Height: eye height clamped into the free space, a slow bob.
  const double bob = std::min(0.15, 0.5 * reach.z());
  p[2].offset = std::clamp(options.eye_height, box.min().z() + bob + 2.0 * wobble.z(),
                           box.max().z() - bob - 2.0 * wobble.z());

  SmoothSignal yaw, pitch, roll;
  const double turn = options.turn_frequency_scale;
  const double yaw_omega = 0.6 * turn, pitch_omega = 0.9 * turn, roll_omega = 1.3 * turn;
  if (scene.kind == SceneKind::kRoom) {
    const double rx = 0.9 * reach.x(), ry = 0.9 * reach.y();
    const double radius = std::max(0.5 * (rx + ry), 1e-3);
    const double omega = options.speed / radius;
    const double phi = phase();
    p[0].terms.push_back({rx, omega, phi + 0.5 * kPi});  // rx cos(omega t + phi)
    p[1].terms.push_back({ry, omega, phi});              // ry sin(omega t + phi)
    p[2].terms.push_back({bob, 0.5 * omega, phase()});
    // Heading along the motion (theta + pi/2), turned 0.3 rad towards the room centre (so the
    // far walls are in view), with a sway.
    yaw.offset = phi + 0.5 * kPi + 0.3;
    yaw.rate = omega;
    yaw.terms.push_back({0.5 * options.yaw_sway, yaw_omega, phase()});
  } else {
    // Back and forth along x, always looking towards +x (down the corridor / street) with a yaw
    // sway; the +x end of the motion stays `lookahead` metres short of the free space so that
    // the end wall / the far facades remain in view.
    const double lookahead = std::min(8.0, 0.4 * box.sizes().x());
    const double x_lo = box.min().x() + 2.0 * wobble.x();
    const double x_hi = box.max().x() - 2.0 * wobble.x() - lookahead;
    const double X = 0.5 * std::max(x_hi - x_lo, 0.0), Y = 0.7 * reach.y();
    const double omega = options.speed / std::max(X, 1e-3);
    p[0].offset = 0.5 * (x_lo + x_hi);
    p[0].terms.push_back({X, omega, phase()});
    p[1].terms.push_back({Y, 1.7 * omega + 0.2, phase()});
    p[2].terms.push_back({bob, 0.5 * omega + 0.3, phase()});
    yaw.terms.push_back({options.yaw_sway, yaw_omega, phase()});
    if (scene.kind == SceneKind::kFacades) pitch.offset = -0.12;  // look up at the facades
  }
  for (int i = 0; i < 3; ++i) p[i].terms.push_back({wobble(i), wobble_omega[i], phase()});
  pitch.terms.push_back({options.pitch_amplitude, pitch_omega, phase()});
  roll.terms.push_back({options.roll_amplitude, roll_omega, phase()});
  Trajectory trajectory(p, yaw, pitch, roll, options.duration);
  trajectory.SetStandingStart(options.standing_start_s, options.start_ramp_s);
  return trajectory;
}

void MakeAggressive(TrajectoryOptions* options) {
  options->speed = 5.0;
  options->yaw_sway = 0.6;
  options->pitch_amplitude = 0.15;
  options->roll_amplitude = 0.1;
  options->wobble = 0.1;
  options->turn_frequency_scale = 3.0;
}

void MakeFast(TrajectoryOptions* options) {
  MakeAggressive(options);
  options->speed = 7.3;
  options->yaw_sway = 0.8;
  options->turn_frequency_scale = 4.0;
}

}  // namespace sim
}  // namespace plucker
