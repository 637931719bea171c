// IMU synthesis from an analytic trajectory:
//   gyro  = omega_b(t) + b_g + n_g,            n_g ~ N(0, sigma_g^2 / dt)   per axis
//   accel = R_w_b(t)^T (a_w(t) - g_w) + b_a + n_a, n_a ~ N(0, sigma_a^2 / dt)
//   b_{k+1} = b_k + N(0, sigma_bw^2 dt)        (bias random walks)
// with sigma_* the continuous-time densities (sigma_d = sigma_c / sqrt(dt), dt = 1 / rate).
// Deterministic given the seed; no I/O.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "plucker/sensor/imu.h"
#include "plucker/sim/trajectory.h"

namespace plucker {
namespace sim {

struct ImuOptions {
  sensor::ImuModel model;  // rate, noise densities and bias random walks
  Eigen::Vector3d initial_gyro_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d initial_accel_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d gravity_w{0.0, 0.0, -9.81};
};

// Samples at t_k = k / rate_hz for k = 0 .. ceil(duration * rate_hz) (rate_hz of options.model)
// (the last sample is at or after the trajectory's end). Throws std::invalid_argument for a
// non-positive rate or negative / non-finite densities.
std::vector<sensor::ImuSample> SimulateImu(const Trajectory& trajectory, const ImuOptions& options,
                                           std::uint64_t seed);

}  // namespace sim
}  // namespace plucker
