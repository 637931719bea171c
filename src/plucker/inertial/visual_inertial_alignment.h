// Dynamic initialisation: up-to-scale camera poses of the first keyframes (visual SfM) aligned
// with the IMU preintegrated between them, in the manner of VINS-Mono (Qin et al., TRO 2018)
// (docs/math/vi-initialisation.md, "Dynamic initialisation"). Steps:
//   (a) gyro bias: linear least squares on the rotation differences with the preintegration's
//       bias Jacobian, then every preintegration is integrated again at the new bias;
//   (b) one weighted linear solve for the keyframe velocities, gravity in the first camera frame
//       c0 and the metric scale of the visual translations;
//   (c) gravity refined on the sphere of radius |g| (2-DoF tangent), with the velocities, the
//       scale and the accelerometer bias (with a prior) solved again; then a world frame w is
//       chosen with gravity along -z and the yaw of the first body frame zero.
// Failures are results with a reason, not exceptions: scale <= 0, |g| far from its value after
// (b), or too little excitation (the scale's standard deviation from the IMU noise model is too
// large a fraction of the scale, or the system is rank-deficient, as for constant-velocity
// motion). The accelerometer bias is estimated in step (c) with a prior (it is weakly observable
// over a few seconds: it trades against the gravity direction unless the body rotates).
//
// No I/O, no printing, no timing.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "plucker/factors/imu_preintegration.h"
#include "plucker/geometry/se3.h"
#include "plucker/sensor/body_state.h"

namespace plucker {
namespace inertial {

struct AlignmentOptions {
  double gravity_magnitude = 9.81;        // m/s^2
  double max_gravity_deviation = 1.0;     // m/s^2, | |g_c0| - |g| | allowed after step (b)
  double max_scale_relative_sigma = 0.1;  // sigma(s) / s allowed after step (c)
  // The root mean square of the whitened residuals of step (c) allowed (about 1 when the visual
  // poses and the IMU agree with their noise models; simulated and EuRoC starts give 0.3-1.6).
  // Far above it, the up-to-scale trajectory is not one the IMU measured (e.g. a vision-only run
  // whose scale drifted: 19.7 on a simulated corridor, seed 212 at 20 Hz, with an accelerometer
  // bias of 1.6 m/s^2 absorbing the difference). Infinity: not checked.
  double max_whitened_rms = 5.0;
  // Noise of the visual keyframe positions at metric scale, added to the position rows of the
  // weights (m). The IMU part comes from each preintegration's covariance.
  double visual_position_sigma = 0.005;
  // Prior standard deviation of the accelerometer bias around the preintegrations' linearisation
  // value, estimated in step (c) to first order (dp_dba, dv_dba); 0 holds it at that value.
  double accel_bias_prior_sigma = 0.2;  // m/s^2
  // The accelerometer bias step (c) needs, in sigmas of that prior (|b_a - b_lin| / sigma),
  // allowed. Far above it, the bias absorbs what the visual poses and the IMU disagree on while
  // the whitened rms stays under max_whitened_rms: a simulated corridor at 30 Hz under fast turns
  // (7.7 m/s, 2 rad/s, seed 210) aligned a vision-only run with a scale 0.29 of the true one and a
  // bias of 1.05 m/s^2 (5.2 sigmas; true 0), rms 3.1, and the window drifted 28 m in 10 s.
  // Starts measured: the EuRoC MH_05 take-off 2.35 sigmas (its bias carries the gravity tilt),
  // simulated room and corridor starts under 1. Infinity: not checked.
  double max_accel_bias_sigmas = 4.0;
  int gyro_bias_iterations = 2;  // step (a) re-linearised this often
  int gravity_iterations = 4;    // step (c)
  int min_keyframes = 4;
};

struct AlignmentInput {
  std::vector<SE3d> T_c0_ck;  // camera poses of keyframes 0..N-1, translations up to scale
  SE3d T_b_c;                 // camera in the body (IMU) frame, metric
  // preintegrations[k] integrates the IMU from keyframe k to k + 1 (N - 1 of them), at any
  // linearisation bias (usually zero); copies are integrated again at the estimated gyro bias.
  std::vector<ImuPreintegration> preintegrations;
  double t0 = 0.0;  // s, the time of keyframe 0 (the states' times are t0 plus the spans)
};

enum class AlignmentStatus {
  kSuccess,
  kTooFewKeyframes,
  kNotExcited,  // rank-deficient or too uncertain scale
  kNonPositiveScale,
  kGravityMagnitude,  // |g| far from gravity_magnitude after step (b)
  kInconsistent,      // the residuals far above their noise models (max_whitened_rms)
};
const char* ToString(AlignmentStatus status);

struct AlignmentResult {
  AlignmentStatus status = AlignmentStatus::kTooFewKeyframes;
  std::string message;
  bool success() const { return status == AlignmentStatus::kSuccess; }

  double scale = 0.0;                   // metric = scale * visual translation
  double scale_sigma = 0.0;             // standard deviation from the IMU noise model (step (c))
  double gravity_norm_unrefined = 0.0;  // |g_c0| after step (b)
  Eigen::Vector3d gravity_c0 = Eigen::Vector3d::Zero();  // refined, |g| = gravity_magnitude
  Eigen::Matrix3d R_w_c0 = Eigen::Matrix3d::Identity();  // gravity along -z in w
  sensor::ImuBias bias;                                  // estimated
  // The body at each keyframe: metric pose T_w_b and velocity in w, the estimated bias.
  std::vector<sensor::BodyState> states;
  std::vector<ImuPreintegration> preintegrations;  // integrated again at `bias`
  // Root mean square of the whitened residuals of the final linear system, its size.
  double whitened_rms = 0.0;
  int rows = 0, unknowns = 0;
};

// Throws std::invalid_argument when the input sizes do not match (N poses, N - 1
// preintegrations) or a value is not finite.
AlignmentResult AlignVisualInertial(const AlignmentInput& input,
                                    const AlignmentOptions& options = {});

// The gyro bias of step (a) alone: minimises sum_k |Log(DR_k(b)^T R_bk_bk+1)|^2 with
// DR_k(b) ~ DR_k Exp(dR_dbg (b - b_lin)), R_bk_bk+1 from the camera poses and R_b_c.
// Returns the bias (the linearisation bias of preintegrations[0] plus the correction).
Eigen::Vector3d EstimateGyroBias(const std::vector<SE3d>& T_c0_ck, const SE3d& T_b_c,
                                 const std::vector<ImuPreintegration>& preintegrations);

}  // namespace inertial
}  // namespace plucker
