// Test helpers (not installed): a smooth 3D motion that excites an IMU on every axis, and
// noise-free IMU readings along it.
#pragma once

#include <vector>

#include "plucker/sensor/imu.h"
#include "plucker/sim/imu.h"
#include "plucker/sim/trajectory.h"

namespace plucker {
namespace sim {

// About 1 m/s with turns of up to ~1 rad/s about every axis.
inline Trajectory ExcitingTestTrajectory(double duration) {
  auto signal = [](double offset, double rate, double a, double w, double phi) {
    SmoothSignal s;
    s.offset = offset;
    s.rate = rate;
    s.terms = {{a, w, phi}, {0.3 * a, 2.7 * w, 2 * phi + 0.5}};
    return s;
  };
  return Trajectory({signal(0, 0.8, 1.0, 0.9, 0.1), signal(1, 0.1, 0.8, 1.1, 0.7),
                     signal(1.5, 0.0, 0.3, 1.7, 1.3)},
                    signal(0.2, 0.3, 0.6, 0.8, 0.4), signal(0, 0, 0.15, 1.3, 0.2),
                    signal(0, 0, 0.1, 1.9, 0.9), duration);
}

// Readings without noise or bias drift, at rate_hz, with constant biases.
inline std::vector<sensor::ImuSample> NoiseFreeImu(const Trajectory& traj, double rate_hz,
                                                   const Eigen::Vector3d& gyro_bias,
                                                   const Eigen::Vector3d& accel_bias,
                                                   const Eigen::Vector3d& gravity_w) {
  ImuOptions o;
  o.model.rate_hz = rate_hz;
  o.model.gyro_noise_density = o.model.accel_noise_density = 0.0;
  o.model.gyro_bias_random_walk = o.model.accel_bias_random_walk = 0.0;
  o.initial_gyro_bias = gyro_bias;
  o.initial_accel_bias = accel_bias;
  o.gravity_w = gravity_w;
  return SimulateImu(traj, o, 1);
}

}  // namespace sim
}  // namespace plucker
