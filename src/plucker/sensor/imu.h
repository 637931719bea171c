// IMU measurements: angular rate and specific force in the body (IMU) frame b.
#pragma once

#include <Eigen/Core>

namespace plucker {
namespace sensor {

// How an IMU is described (EuRoC's sensor.yaml gives the same values): its sample rate and the
// continuous-time white-noise densities and bias random walks. The discrete per-sample sigmas are
// density / sqrt(dt) (white noise) and random_walk * sqrt(dt) (bias step), dt = 1 / rate_hz.
struct ImuModel {
  double rate_hz = 200.0;
  double gyro_noise_density = 1.7e-4;      // rad / s / sqrt(Hz)
  double accel_noise_density = 2.0e-3;     // m / s^2 / sqrt(Hz)
  double gyro_bias_random_walk = 2.0e-5;   // rad / s^2 / sqrt(Hz)
  double accel_bias_random_walk = 3.0e-3;  // m / s^3 / sqrt(Hz)
};

// The IMU biases: gyro + gyro_bias and accel + accel_bias are what the sensor reports.
struct ImuBias {
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();   // rad / s
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();  // m / s^2
};

struct ImuSample {
  double t = 0.0;                                        // s
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();        // rad/s, body frame
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();       // m/s^2, specific force, body frame
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();   // ground truth at t (zero if unknown)
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();  // ground truth at t (zero if unknown)
};

}  // namespace sensor
}  // namespace plucker
