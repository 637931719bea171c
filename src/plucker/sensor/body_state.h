// The full inertial state of the body (IMU) frame b at a time: pose in the world, world-frame
// velocity and the IMU biases. Ground truth of visual-inertial datasets (EuRoC's
// state_groundtruth_estimate0) and the estimate of a visual-inertial estimator have this form.
#pragma once

#include <Eigen/Core>

#include "plucker/geometry/se3.h"
#include "plucker/sensor/imu.h"

namespace plucker {
namespace sensor {

struct BodyState {
  double t = 0.0;  // s
  SE3d T_w_b;
  Eigen::Vector3d v_w = Eigen::Vector3d::Zero();  // m/s, world frame
  ImuBias bias;
};

}  // namespace sensor
}  // namespace plucker
