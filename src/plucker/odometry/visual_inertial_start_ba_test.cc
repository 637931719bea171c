// The dynamic start's visual-inertial bundle adjustment (visual_inertial_start_ba.h): on a
// simulated room, a start whose gravity is tilted 3 deg (every state rotated about the world x
// axis, as a poorly excited alignment leaves it) comes out of the step within 1 deg of the truth.
#include "plucker/odometry/visual_inertial_start_ba.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "plucker/odometry/vio_test_utils.h"
#include "plucker/sim/camera_observations.h"

namespace plucker {
namespace odometry {
namespace {

using Input = VioTestInput;

Input Simulate(int num_frames) {
  sim::CameraSimulationOptions o;
  o.scene.kind = sim::SceneKind::kRoom;
  o.num_frames = num_frames;
  o.seed = 3;
  return VioInputFromSimulation(sim::SimulateCamera(o), /*every_other_point=*/true);
}

// The angle between the estimated and true gravity directions in the body (deg).
double TiltDeg(const SE3d& T_w_b, const SE3d& gt_T_w_b) {
  const Eigen::Vector3d up(0.0, 0.0, 1.0);
  const Eigen::Vector3d a = T_w_b.rotation().inverse() * up;
  const Eigen::Vector3d b = gt_T_w_b.rotation().inverse() * up;
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

sensor::BodyState Tilted(const sensor::BodyState& s, const SE3d& T_tilt) {
  sensor::BodyState t = s;
  t.T_w_b = T_tilt * s.T_w_b;
  t.v_w = T_tilt.rotation() * s.v_w;
  return t;
}

// The initialisation run on the frames until it decides; frames: those given to it.
bool RunInitializer(const VisualInertialOdometryOptions& o, const Input& in,
                    std::vector<window::FrameInput>* frames, VioStart* start) {
  VisualInertialInitializer init(o, in.calib);
  std::vector<inertial::ImageMotionFlag> flags;
  bool done = false;
  for (std::size_t i = 0; i < in.frames.size() && !done; ++i) {
    frames->push_back(in.frames[i]);
    if (i > 0) {
      const auto flag = ImageMotion((*frames)[i - 1], (*frames)[i], o.image_still_px);
      if (flag) flags.push_back(*flag);
    }
    done = init.Advance(*frames, in.imu, flags, i + 1 == in.frames.size());
  }
  if (done) *start = init.start();
  return done;
}

TEST(StartBundleAdjustment, RemovesAGravityTiltOfTheAlignment) {
  const Input in = Simulate(80);
  VisualInertialOdometryOptions o;
  o.use_lines = false;
  o.init_ba_iterations = 20;
  std::vector<window::FrameInput> frames;
  VioStart start;
  ASSERT_TRUE(RunInitializer(o, in, &frames, &start));
  ASSERT_EQ(start.method, "dynamic");
  ASSERT_GE(start.candidates.size(), 5u);
  // The whole start rotated 3 deg about the world x axis (its positions and velocities too).
  const SE3d T_tilt(
      Eigen::Quaterniond(Eigen::AngleAxisd(3.0 * M_PI / 180.0, Eigen::Vector3d::UnitX())),
      Eigen::Vector3d::Zero());
  for (auto& s : start.candidate_states) s = Tilted(s, T_tilt);
  start.state_first = Tilted(start.state_first, T_tilt);
  start.state_second = Tilted(start.state_second, T_tilt);
  for (auto& T : start.T_w_b)
    if (T) T = T_tilt * *T;
  const double before = TiltDeg(start.state_second.T_w_b, in.gt_T_w_b[start.second]);
  EXPECT_GT(before, 2.0);

  const StartAdjustmentSummary r = AdjustDynamicStart(o, in.calib, frames, in.imu, &start);
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.keyframes, static_cast<int>(start.candidates.size()) + 1);
  EXPECT_GT(r.points, 20);
  const double after_second = TiltDeg(start.state_second.T_w_b, in.gt_T_w_b[start.second]);
  const double after_first =
      TiltDeg(start.candidate_states.front().T_w_b, in.gt_T_w_b[start.candidates.front()]);
  EXPECT_LT(after_second, 1.0) << "before " << before;
  EXPECT_LT(after_first, 1.0);
  EXPECT_NEAR(r.tilt_change_deg, before - after_second, 1.0);
  // The poses written for the frames up to the start moved with it.
  ASSERT_TRUE(start.T_w_b[start.second]);
  EXPECT_LT(TiltDeg(*start.T_w_b[start.second], in.gt_T_w_b[start.second]), 1.0);
}

// init_accel_bias / init_gyro_bias: the solve starts from the given biases and keeps them (the
// gyro bias held, the accel bias with a tight prior).
TEST(StartBundleAdjustment, KeepsGivenBiases) {
  const Input in = Simulate(80);
  VisualInertialOdometryOptions o;
  o.use_lines = false;
  o.init_ba_iterations = 10;
  o.init_ba_accel_bias_prior_sigma = 1e-3;
  o.init_accel_bias = Eigen::Vector3d(0.02, -0.01, 0.015);
  o.init_gyro_bias = Eigen::Vector3d(1e-3, -2e-3, 5e-4);
  std::vector<window::FrameInput> frames;
  VioStart start;
  ASSERT_TRUE(RunInitializer(o, in, &frames, &start));
  ASSERT_EQ(start.method, "dynamic");
  const StartAdjustmentSummary r = AdjustDynamicStart(o, in.calib, frames, in.imu, &start);
  ASSERT_TRUE(r.ok);
  EXPECT_LT((start.state_first.bias.accel - *o.init_accel_bias).norm(), 5e-3);
  EXPECT_LT((start.state_first.bias.gyro - *o.init_gyro_bias).norm(), 5e-4);
  EXPECT_LT((start.state_second.bias.gyro - *o.init_gyro_bias).norm(), 1e-3);
}

// init_extend_keyframes: the start is aligned again after that many keyframes more (at most
// init_max_keyframes), on the same run: the same first keyframe, a later second.
TEST(StartBundleAdjustment, ExtendedStartHasMoreKeyframes) {
  const Input in = Simulate(120);
  VisualInertialOdometryOptions o;
  o.use_lines = false;
  std::vector<window::FrameInput> frames;
  VioStart first, extended;
  ASSERT_TRUE(RunInitializer(o, in, &frames, &first));
  ASSERT_EQ(first.method, "dynamic");
  o.init_extend_keyframes = 5;
  frames.clear();
  ASSERT_TRUE(RunInitializer(o, in, &frames, &extended));
  ASSERT_EQ(extended.method, "dynamic");
  EXPECT_EQ(extended.candidates.front(), first.candidates.front());
  const std::size_t most = static_cast<std::size_t>(o.init_max_keyframes);
  EXPECT_EQ(extended.candidates.size(), std::min(first.candidates.size() + 5, most - 1));
  EXPECT_GT(extended.second, first.second);
  EXPECT_EQ(extended.T_w_b.size(), static_cast<std::size_t>(extended.second) + 1);
}

// init_min_span_s: the alignment waits until the run's keyframes span that long (the same run:
// the same first keyframe, a later second one at least that far from it).
TEST(StartBundleAdjustment, AlignmentWaitsForItsSpan) {
  const Input in = Simulate(120);
  VisualInertialOdometryOptions o;
  o.use_lines = false;
  o.init_min_span_s = 0.0;
  std::vector<window::FrameInput> frames;
  VioStart first, longer;
  ASSERT_TRUE(RunInitializer(o, in, &frames, &first));
  ASSERT_EQ(first.method, "dynamic");
  const double span = frames[first.second].time - frames[first.candidates.front()].time;
  o.init_min_span_s = span + 0.5;
  frames.clear();
  ASSERT_TRUE(RunInitializer(o, in, &frames, &longer));
  ASSERT_EQ(longer.method, "dynamic");
  std::printf("start span %.2f s, with init_min_span_s %.2f: %.2f s\n", span, o.init_min_span_s,
              frames[longer.second].time - frames[longer.candidates.front()].time);
  EXPECT_EQ(longer.candidates.front(), first.candidates.front());
  EXPECT_GE(frames[longer.second].time - frames[longer.candidates.front()].time, span + 0.5);
}

TEST(StartBundleAdjustment, LeavesTooShortAStartAsItWas) {
  const Input in = Simulate(10);
  VisualInertialOdometryOptions o;
  o.init_ba_iterations = 5;
  VioStart start;
  start.method = "dynamic";
  start.second = 1;
  start.candidates = {0};
  start.candidate_states.resize(1);
  const StartAdjustmentSummary r = AdjustDynamicStart(o, in.calib, in.frames, in.imu, &start);
  EXPECT_TRUE(r.ran);
  EXPECT_FALSE(r.ok);
}

}  // namespace
}  // namespace odometry
}  // namespace plucker
