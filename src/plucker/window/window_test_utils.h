// Test scaffolding shared by the window's visual-inertial tests (not installed).
#pragma once

#include <cstddef>

#include "plucker/sim/camera_observations.h"
#include "plucker/window/sliding_window_estimator.h"

namespace plucker {
namespace window {

// The simulation's true state at frame i: body pose, velocity, and the biases of the IMU sample
// nearest the frame (at or before its time).
inline sensor::BodyState TrueState(const sim::CameraSimulation& s, int i) {
  sensor::BodyState st;
  st.T_w_b = s.T_w_b_gt[i];
  st.v_w = s.v_w_gt[i];
  std::size_t k = 0;
  while (k + 1 < s.imu.size() && s.imu[k + 1].t <= s.frame_times[i]) ++k;
  st.bias.gyro = s.imu[k].gyro_bias;
  st.bias.accel = s.imu[k].accel_bias;
  return st;
}

}  // namespace window
}  // namespace plucker
