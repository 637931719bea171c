// IMU measurements: angular rate and specific force in the body (IMU) frame b.
#pragma once

#include <Eigen/Core>

namespace plucker {
namespace sensor {

struct ImuSample {
  double t = 0.0;                                        // s
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();        // rad/s, body frame
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();       // m/s^2, specific force, body frame
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();   // ground truth at t (zero if unknown)
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();  // ground truth at t (zero if unknown)
};

}  // namespace sensor
}  // namespace plucker
