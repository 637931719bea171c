#include "plucker/sim/trajectory.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "plucker/geometry/so3.h"

namespace plucker {
namespace sim {
namespace {

TEST(SmoothSignalTest, DerivativesMatchCentralDifferences) {
  SmoothSignal s;
  s.offset = 0.3;
  s.rate = -0.7;
  s.terms = {{1.2, 0.8, 0.1}, {0.05, 7.0, 2.0}};
  const double h = 1e-5;
  for (double t = -3.0; t < 3.0; t += 0.37) {
    EXPECT_NEAR(s.FirstDerivative(t), (s.Value(t + h) - s.Value(t - h)) / (2 * h), 1e-8);
    EXPECT_NEAR(s.SecondDerivative(t),
                (s.FirstDerivative(t + h) - s.FirstDerivative(t - h)) / (2 * h), 1e-8);
  }
}

class TrajectoryKindTest : public ::testing::TestWithParam<SceneKind> {
 protected:
  void SetUp() override {
    SceneOptions scene_options;
    scene_options.kind = GetParam();
    scene_ = MakeScene(scene_options, 11);
    TrajectoryOptions options;
    options.duration = 20.0;
    options.wobble = 0.08;
    trajectory_ = MakeTrajectory(options, scene_, 5);
  }
  Scene scene_;
  Trajectory trajectory_;
};

TEST_P(TrajectoryKindTest, AnalyticDerivativesMatchCentralDifferences) {
  const Trajectory& tr = trajectory_;
  const double h = 1e-5;
  double max_v = 0, max_a = 0, max_w = 0;
  for (double t = 0.0; t <= tr.duration(); t += 0.173) {
    const Eigen::Vector3d v_fd = (tr.position_w(t + h) - tr.position_w(t - h)) / (2 * h);
    const Eigen::Vector3d a_fd = (tr.velocity_w(t + h) - tr.velocity_w(t - h)) / (2 * h);
    // R(t + h) = R(t - h) Exp(2 h omega_b(t)) + O(h^3).
    const Eigen::Quaterniond dq(tr.R_w_b(t - h).transpose() * tr.R_w_b(t + h));
    const Eigen::Vector3d w_fd = LogSO3(dq) / (2 * h);
    max_v = std::max(max_v, (tr.velocity_w(t) - v_fd).norm());
    max_a = std::max(max_a, (tr.acceleration_w(t) - a_fd).norm());
    max_w = std::max(max_w, (tr.angular_velocity_b(t) - w_fd).norm());
    EXPECT_NEAR((tr.angular_velocity_w(t) - tr.R_w_b(t) * w_fd).norm(), 0.0, 1e-6);
    // T_w_b agrees with R_w_b and position_w.
    EXPECT_LT((tr.T_w_b(t).RotationMatrix() - tr.R_w_b(t)).norm(), 1e-12);
    EXPECT_EQ(tr.T_w_b(t).translation(), tr.position_w(t));
  }
  EXPECT_LT(max_v, 1e-7);
  EXPECT_LT(max_a, 1e-7);
  EXPECT_LT(max_w, 1e-6);
}

TEST_P(TrajectoryKindTest, StaysInFreeSpaceAndMoves) {
  const Trajectory& tr = trajectory_;
  const Eigen::AlignedBox3d box = scene_.free_space_w;
  double path = 0.0, turned = 0.0;
  Eigen::Vector3d previous = tr.position_w(0.0);
  for (double t = 0.0; t <= tr.duration(); t += 0.05) {
    const Eigen::Vector3d p = tr.position_w(t);
    EXPECT_TRUE(box.contains(p)) << "t = " << t << " p = " << p.transpose();
    path += (p - previous).norm();
    previous = p;
    turned += tr.angular_velocity_b(t).norm() * 0.05;
    EXPECT_LT(std::abs(tr.euler_zyx(t)(1)), 0.5);  // far from the Euler singularity
  }
  EXPECT_GT(path, 5.0);
  EXPECT_GT(turned, 1.0);
}

INSTANTIATE_TEST_SUITE_P(AllKinds, TrajectoryKindTest,
                         ::testing::Values(SceneKind::kRoom, SceneKind::kCorridor,
                                           SceneKind::kFacades),
                         [](const ::testing::TestParamInfo<SceneKind>& info) {
                           return SceneKindName(info.param);
                         });

TEST(TrajectoryTest, DeterministicGivenSeed) {
  const Scene scene = MakeScene(SceneOptions(), 1);
  const Trajectory a = MakeTrajectory(TrajectoryOptions(), scene, 9);
  const Trajectory b = MakeTrajectory(TrajectoryOptions(), scene, 9);
  const Trajectory c = MakeTrajectory(TrajectoryOptions(), scene, 10);
  for (double t : {0.0, 1.5, 4.0}) {
    EXPECT_EQ(a.position_w(t), b.position_w(t));
    EXPECT_EQ(a.R_w_b(t), b.R_w_b(t));
    EXPECT_NE(a.position_w(t), c.position_w(t));
  }
}

TEST(TrajectoryTest, StandingStartStandsThenMovesSmoothly) {
  const Scene scene = MakeScene(SceneOptions(), 1);
  TrajectoryOptions moving;
  moving.duration = 6.0;
  TrajectoryOptions standing = moving;
  standing.standing_start_s = 1.25;
  standing.start_ramp_s = 1.0;
  const Trajectory a = MakeTrajectory(moving, scene, 4);
  const Trajectory b = MakeTrajectory(standing, scene, 4);
  for (double t = 0.0; t <= 1.25; t += 0.05) {  // standing at the moving start's t = 0 pose
    EXPECT_EQ(b.position_w(t), a.position_w(0.0));
    EXPECT_EQ(b.R_w_b(t), a.R_w_b(0.0));
    EXPECT_EQ(b.velocity_w(t).norm(), 0.0);
    EXPECT_EQ(b.acceleration_w(t).norm(), 0.0);
    EXPECT_EQ(b.angular_velocity_b(t).norm(), 0.0);
  }
  // After the ramp: the moving path, delayed by stand + ramp / 2.
  for (double t = 2.3; t <= 6.0; t += 0.4) {
    EXPECT_LT((b.position_w(t) - a.position_w(t - 1.75)).norm(), 1e-12);
    EXPECT_LT((b.velocity_w(t) - a.velocity_w(t - 1.75)).norm(), 1e-12);
  }
  // The derivatives across the stand, the ramp and after, off the joints (1.25 s, 2.25 s: the
  // acceleration is continuous there, its derivative is not, which the central difference of the
  // velocity would see as an O(h) error).
  const double h = 1e-5;
  for (double t = 1.01; t <= 3.0; t += 0.0625) {
    const Eigen::Vector3d v_fd = (b.position_w(t + h) - b.position_w(t - h)) / (2 * h);
    const Eigen::Vector3d a_fd = (b.velocity_w(t + h) - b.velocity_w(t - h)) / (2 * h);
    const Eigen::Quaterniond dq(b.R_w_b(t - h).transpose() * b.R_w_b(t + h));
    EXPECT_LT((b.velocity_w(t) - v_fd).norm(), 1e-7) << t;
    EXPECT_LT((b.acceleration_w(t) - a_fd).norm(), 1e-5) << t;
    EXPECT_LT((b.angular_velocity_b(t) - LogSO3(dq) / (2 * h)).norm(), 1e-6) << t;
  }
  EXPECT_GT(b.velocity_w(2.5).norm(), 0.1);
  standing.standing_start_s = -1.0;
  EXPECT_THROW(MakeTrajectory(standing, scene, 4), std::invalid_argument);
}

// Drives a preset (MakeAggressive, MakeFast) over 20 s in both scenes, seeds 1-5: the path stays
// in free space, and its top speed and turn rate fall within the given bounds.
struct MotionBounds {
  double min_v, max_v, min_w, max_w;
};

void ExpectPresetWithin(void (*preset)(TrajectoryOptions*), double step_s, const MotionBounds& b) {
  for (const SceneKind kind : {SceneKind::kRoom, SceneKind::kCorridor}) {
    SceneOptions scene_options;
    scene_options.kind = kind;
    const Scene scene = MakeScene(scene_options, 3);
    TrajectoryOptions options;
    options.duration = 20.0;
    preset(&options);
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      const Trajectory tr = MakeTrajectory(options, scene, seed);
      double max_v = 0.0, max_w = 0.0;
      for (double t = 0.0; t <= tr.duration(); t += step_s) {
        EXPECT_TRUE(scene.free_space_w.contains(tr.position_w(t))) << SceneKindName(kind) << t;
        max_v = std::max(max_v, tr.velocity_w(t).norm());
        max_w = std::max(max_w, tr.angular_velocity_b(t).norm());
      }
      EXPECT_GT(max_v, b.min_v) << SceneKindName(kind) << " seed " << seed;
      EXPECT_LT(max_v, b.max_v) << SceneKindName(kind) << " seed " << seed;
      EXPECT_GT(max_w, b.min_w) << SceneKindName(kind) << " seed " << seed;
      EXPECT_LT(max_w, b.max_w) << SceneKindName(kind) << " seed " << seed;
    }
  }
}

TEST(TrajectoryTest, AggressiveMotionIsFastAndStaysInFreeSpace) {
  ExpectPresetWithin(&MakeAggressive, 0.02, {4.0, 8.5, 1.0, 3.0});
}

// Issue 26's fast scene: speeds of 7.5-10 m/s (the room: the lap and sway add up) and turns of at
// least 2 rad/s in both scenes.
TEST(TrajectoryTest, FastMotionReachesEightMetresAndTwoRadiansPerSecond) {
  ExpectPresetWithin(&MakeFast, 0.01, {7.5, 10.0, 2.0, 5.0});
}

TEST(TrajectoryTest, RejectsInvalidOptions) {
  const Scene scene = MakeScene(SceneOptions(), 1);
  TrajectoryOptions options;
  options.speed = 0.0;
  EXPECT_THROW(MakeTrajectory(options, scene, 1), std::invalid_argument);
  options = TrajectoryOptions();
  options.duration = std::nan("");
  EXPECT_THROW(MakeTrajectory(options, scene, 1), std::invalid_argument);
  options = TrajectoryOptions();
  options.pitch_amplitude = 1.2;
  EXPECT_THROW(MakeTrajectory(options, scene, 1), std::invalid_argument);
  Scene empty;
  EXPECT_THROW(MakeTrajectory(TrajectoryOptions(), empty, 1), std::invalid_argument);
}

}  // namespace
}  // namespace sim
}  // namespace plucker
