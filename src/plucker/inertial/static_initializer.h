// Static initialisation: gravity direction and IMU biases from a period in which the body stands
// still (docs/math/vi-initialisation.md, "Static initialisation").
//
// Still test: the IMU log is cut into blocks of `block_seconds`; a block is still when the
// spread of its readings (the root of the trace of the sample covariance) stays below
// max_gyro_std and max_accel_std, and no camera frame inside it was flagged as moving by the
// caller (zero image motion, optional). The still span is the run of still blocks from the
// start of the log (or of `t_begin`); its last block is dropped (the start of the motion is
// gradual) and the rest is used if it lasts at least min_still_seconds.
//
// Estimates over the span's N samples (means a_bar, w_bar, sample covariances S_a, S_w):
//   gyro bias    b_g = w_bar,                       Cov = S_w / N
//   up direction u_b = a_bar / |a_bar|               (R_w_b with zero yaw: gravity.h)
//   accel bias   b_a = (|a_bar| - |g|) u_b          (the component along gravity only)
// With |g| known, one still attitude observes 1 of the 3 accelerometer bias components: a bias
// b_h orthogonal to gravity is indistinguishable from a tilt of |b_h| / |g| rad (0.073 m/s^2, the
// EuRoC V1_01 ground truth's horizontal bias, tilts by 0.42 deg). The horizontal part is taken as
// the caller's prior (zero by default) with the standard deviation accel_bias_prior_sigma per
// axis, which enters the covariances of the up direction and of the bias.
//
// No I/O, no printing, no timing.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "plucker/factors/imu_preintegration.h"
#include "plucker/sensor/imu.h"

namespace plucker {
namespace inertial {

struct StaticInitOptions {
  double block_seconds = 0.25;  // length of one block of the still test
  // Spread of the readings inside a block. A drone with its rotors running vibrates: EuRoC
  // V1_01 standing still shows ~0.75 m/s^2 and ~0.05 rad/s; taking off, several m/s^2.
  double max_accel_std = 1.5;       // m/s^2
  double max_gyro_std = 0.15;       // rad/s
  double min_still_seconds = 1.0;   // shortest usable span (after dropping its last block)
  double gravity_magnitude = 9.81;  // m/s^2, local |g|
  // | |a_bar| - |g| | above this is not a bias but wrong units, a wrong |g| or motion.
  double max_gravity_deviation = 0.5;   // m/s^2
  double accel_bias_prior_sigma = 0.1;  // m/s^2 per axis, the unobservable horizontal part
  Eigen::Vector3d accel_bias_prior = Eigen::Vector3d::Zero();  // m/s^2, body frame
};

// A camera frame the caller knows to show (or not) zero image motion, e.g. from the median
// feature displacement against the previous frame.
struct ImageMotionFlag {
  double t = 0.0;  // s, on the IMU clock
  bool still = true;
};

enum class StaticInitStatus {
  kSuccess,
  kNotStill,         // moving from the start, or the still span is shorter than the minimum
  kGravityMismatch,  // the mean specific force is far from |g|
  kTooFewSamples,    // the IMU log does not cover one block
};
const char* ToString(StaticInitStatus status);

struct StaticInitResult {
  StaticInitStatus status = StaticInitStatus::kTooFewSamples;
  std::string message;  // why it failed (empty on success)
  bool success() const { return status == StaticInitStatus::kSuccess; }

  // The still test.
  double still_begin = 0.0, still_end = 0.0;  // s, the span used
  int blocks_still = 0;                       // still blocks at the start (before dropping one)
  int samples_used = 0;
  double first_moving_block_accel_std = 0.0;  // m/s^2 (0 if none)

  // Estimates.
  Eigen::Matrix3d R_w_b = Eigen::Matrix3d::Identity();      // zero yaw
  Eigen::Vector3d up_b = Eigen::Vector3d::UnitZ();          // unit, R_w_b^T e_z
  Eigen::Vector3d gravity_b = Eigen::Vector3d::Zero();      // -|g| up_b
  Eigen::Matrix3d up_covariance = Eigen::Matrix3d::Zero();  // of up_b (rank 2)
  double tilt_sigma = 0.0;  // rad, the largest standard deviation of the up direction
  sensor::ImuBias bias;
  Eigen::Matrix3d gyro_bias_covariance = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d accel_bias_covariance = Eigen::Matrix3d::Zero();

  // Residual spread over the span (per-axis standard deviations of the readings).
  Eigen::Vector3d gyro_std = Eigen::Vector3d::Zero();   // rad/s
  Eigen::Vector3d accel_std = Eigen::Vector3d::Zero();  // m/s^2
  double accel_norm_mean = 0.0;                         // |a_bar|, m/s^2
};

// Runs the still test from the first sample at or after t_begin and estimates on the still span.
// image_flags (optional, any order) veto the blocks that contain a moving frame. Throws
// std::invalid_argument for timestamps that do not increase, non-finite readings or invalid
// options.
StaticInitResult InitializeStatic(const std::vector<sensor::ImuSample>& imu,
                                  const StaticInitOptions& options = {}, double t_begin = -1e300,
                                  const std::vector<ImageMotionFlag>& image_flags = {});

}  // namespace inertial
}  // namespace plucker
