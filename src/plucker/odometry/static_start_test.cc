// The static start of VisualInertialInitializer on the clocks of real rigs: frame times that fall
// between IMU samples (a Kalibr timeshift_cam_imu) and a drone's rotor vibration at rest.
#include <gtest/gtest.h>

#include <vector>

#include "plucker/odometry/visual_inertial_initializer.h"

namespace plucker {
namespace odometry {
namespace {

// 200 Hz at rest for 3 s, then moving (a gyro spread of 0.5 rad/s); the accelerometer vibrates
// by +-vibration(t) on x (a block's spread is its amplitude).
std::vector<sensor::ImuSample> StandingImu(double block2_vibration) {
  std::vector<sensor::ImuSample> imu;
  for (int k = 0; k < 800; ++k) {
    sensor::ImuSample s;
    s.t = k * 0.005;
    const double sign = k % 2 == 0 ? 1.0 : -1.0;
    const double vibration = s.t >= 0.5 && s.t < 0.75 ? block2_vibration : 0.5;
    s.accel = Eigen::Vector3d(sign * vibration, 0.0, 9.81);
    if (s.t >= 3.0) s.gyro = Eigen::Vector3d(sign * 0.5, 0.0, 0.0);
    imu.push_back(s);
  }
  return imu;
}

std::vector<window::FrameInput> Frames(double first_time) {
  std::vector<window::FrameInput> frames(70);
  for (std::size_t i = 0; i < frames.size(); ++i) frames[i].time = first_time + 0.05 * i;
  return frames;
}

VioStart StaticStart(const std::vector<window::FrameInput>& frames,
                     const std::vector<sensor::ImuSample>& imu) {
  VisualInertialInitializer init(VisualInertialOdometryOptions{}, VisualInertialCalibration{});
  EXPECT_TRUE(init.Advance(frames, imu, {}, true));
  EXPECT_FALSE(init.failed());
  return init.start();
}

TEST(VisualInertialStaticStart, StartsOnFrameZeroBetweenTwoImuSamples) {
  // Frame 0 3 ms after the first IMU sample (a timeshift_cam_imu of 0.003 s): the still span
  // begins at the next sample, 2 ms after the frame; the start used to skip frame 0.
  const VioStart start = StaticStart(Frames(0.003), StandingImu(0.5));
  EXPECT_EQ(start.method, "static");
  EXPECT_EQ(start.first, 0);
  EXPECT_EQ(start.second, 1);
}

TEST(VisualInertialStaticStart, RotorVibrationAtRestIsStill) {
  // EuRoC V1_01 at rest: 1.39-1.62 m/s^2 in its third block, over the still test's default bound
  // of 1.5 m/s^2 depending on where the block grid falls.
  const VioStart start = StaticStart(Frames(0.0), StandingImu(1.7));
  EXPECT_EQ(start.method, "static");
  EXPECT_EQ(start.first, 0);
  ASSERT_EQ(start.T_w_b.size(), 2u);
  EXPECT_TRUE(start.T_w_b[0].has_value());
}

TEST(VisualInertialStaticStart, TakeOffIsNotStill) {
  // A block over static_max_accel_std (take-off) ends the still span: 0.5 s is too short.
  VisualInertialOdometryOptions o;
  VisualInertialInitializer init(o, VisualInertialCalibration{});
  init.Advance(Frames(0.0), StandingImu(o.static_max_accel_std + 0.5), {}, true);
  EXPECT_NE(init.start().method, "static");
}

}  // namespace
}  // namespace odometry
}  // namespace plucker
