// Smooth body trajectories with analytic derivatives, for camera/IMU simulation.
//
// Every coordinate is a SmoothSignal: offset + rate * t + sum_k a_k sin(w_k t + phi_k), whose
// first and second derivatives are closed-form. The body position p_w(t) has one signal per axis;
// the orientation is R_w_b(t) = Rz(yaw) Ry(pitch) Rx(roll) with three signals. The body angular
// velocity follows analytically from the Euler-angle rates (docs/sim-format.md):
//   omega_b = [roll' - yaw' sin(pitch),
//              pitch' cos(roll) + yaw' cos(pitch) sin(roll),
//              -pitch' sin(roll) + yaw' cos(pitch) cos(roll)],   R_w_b' = R_w_b [omega_b]x.
// Body frame b: x forward, y left, z up (pitch is kept small, far from the Euler singularity).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "plucker/geometry/se3.h"
#include "plucker/sim/scene.h"

namespace plucker {
namespace sim {

struct Sinusoid {
  double amplitude = 0.0;
  double omega = 0.0;  // rad/s
  double phase = 0.0;  // rad
};

struct SmoothSignal {
  double offset = 0.0;
  double rate = 0.0;  // linear term
  std::vector<Sinusoid> terms;

  double Value(double t) const;
  double FirstDerivative(double t) const;
  double SecondDerivative(double t) const;
};

class Trajectory {
 public:
  Trajectory() = default;
  // position_w: x, y, z signals; euler: yaw, pitch, roll signals (radians).
  Trajectory(const std::array<SmoothSignal, 3>& position_w, const SmoothSignal& yaw,
             const SmoothSignal& pitch, const SmoothSignal& roll, double duration);

  SE3d T_w_b(double t) const;
  Eigen::Matrix3d R_w_b(double t) const;
  Eigen::Vector3d position_w(double t) const;
  Eigen::Vector3d velocity_w(double t) const;
  Eigen::Vector3d acceleration_w(double t) const;
  Eigen::Vector3d angular_velocity_b(double t) const;  // R_w_b^T R_w_b' = [omega_b]x
  Eigen::Vector3d angular_velocity_w(double t) const;  // R_w_b omega_b
  Eigen::Vector3d euler_zyx(double t) const;           // (yaw, pitch, roll)

  // The trajectory is defined for every t; [0, duration] is the simulated interval.
  double duration() const { return duration_; }

  // A standing start: the body stands at its t = 0 pose for `stand_s` seconds, then speeds up
  // smoothly over `ramp_s` seconds to the path's own speed (a time warp u(t): u = 0 while
  // standing, u' a cubic smoothstep from 0 to 1 over the ramp, then u' = 1; the acceleration and
  // angular velocity stay continuous). 0, 0: none (the default).
  void SetStandingStart(double stand_s, double ramp_s);

 private:
  struct Warp {
    double u, du, ddu;  // u(t), u'(t), u''(t)
  };
  Warp WarpAt(double t) const;

  std::array<SmoothSignal, 3> position_w_;
  SmoothSignal yaw_, pitch_, roll_;
  double duration_ = 0.0;
  double stand_s_ = 0.0, ramp_s_ = 0.0;
};

struct TrajectoryOptions {
  double duration = 10.0;         // s (SimulateCamera sets it from the frame count and rate)
  double speed = 1.0;             // m/s, typical speed along the main motion
  double eye_height = 1.5;        // m above the floor/ground (clamped into the free space)
  double yaw_sway = 0.35;         // rad, amplitude of the heading oscillation
  double pitch_amplitude = 0.08;  // rad
  double roll_amplitude = 0.04;   // rad
  double wobble = 0.05;  // m, amplitude of higher-frequency position terms (IMU excitation)
  // Standing start (Trajectory::SetStandingStart): seconds standing still at t = 0, then the
  // seconds of the smooth speed-up (0: the body moves from t = 0, the default).
  double standing_start_s = 0.0;
  // Scales the frequencies of the heading sway, pitch and roll (faster turns; 1: the default).
  double turn_frequency_scale = 1.0;
  double start_ramp_s = 1.0;
};

// A trajectory that stays inside scene.free_space_w and looks at the scene:
//   room:     an ellipse around the centre, heading along the motion turned towards the walls,
//             one lap every 2 pi radius / speed seconds;
//   corridor / facades: back and forth along x, looking towards +x down the corridor / street
//             with a yaw sway so both walls / facades are seen in perspective; the motion stops
//             min(8 m, 40% of the length) short of the +x end so the far end stays in view.
// standing_start_s > 0: the body stands that long first (Trajectory::SetStandingStart).
// Random phases from `seed`. Throws std::invalid_argument for non-finite / non-positive options.
Trajectory MakeTrajectory(const TrajectoryOptions& options, const Scene& scene, std::uint64_t seed);

// The aggressive motion of the robustness table (docs/sim-format.md): fast (speed 5 m/s along
// the main motion, up to ~8 m/s with the sway) with fast turns (the heading sway, pitch and roll
// at 3x their frequencies, larger amplitudes: the room up to ~2.8 rad/s, the corridor ~1.2;
// `plucker sim camera` prints the largest speed and turn rate of a run).
void MakeAggressive(TrajectoryOptions* options);

// The fast motion of issue 26 (speeds up to 8 m/s, turns up to 2 rad/s; docs/sim-format.md):
// speed 7.3 m/s along the main motion (~8 m/s with the sway and wobble), the heading sway 0.8 rad
// at 4x its frequency (the corridor turns at ~2.2 rad/s; the room, whose lap itself turns at
// speed / radius, at ~4 rad/s). MakeAggressive stays as it was (its runs byte-identical).
void MakeFast(TrajectoryOptions* options);

}  // namespace sim
}  // namespace plucker
