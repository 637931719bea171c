// The dynamic start's search within a budget (init_pair_budget, init_pair_min_rotated_parallax_px,
// visual_inertial_initializer.h) on a simulated corridor, whose forward motion gives too little
// parallax for the first pairs: unbounded, the search runs many two-view RANSACs in one frame;
// with a budget never more than that in a frame, and the same start (frames and states), decided
// no earlier. The rotated-parallax test refuses pairs without their RANSAC.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "plucker/odometry/vio_test_utils.h"
#include "plucker/odometry/visual_inertial_initializer.h"
#include "plucker/sim/camera_observations.h"

namespace plucker {
namespace odometry {
namespace {

VioTestInput Simulate(int num_frames) {
  sim::CameraSimulationOptions o;
  o.scene.kind = sim::SceneKind::kCorridor;
  o.num_frames = num_frames;
  o.seed = 1;
  return VioInputFromSimulation(sim::SimulateCamera(o), /*every_other_point=*/false);
}

struct SearchRun {
  bool done = false;
  int decided_at = -1;  // the frame whose Advance decided
  int most_tests = 0;   // the most two-view RANSACs of one Advance
  int tests = 0;        // in all
  VioStart start;
};

SearchRun RunSearch(const VisualInertialOdometryOptions& o, const VioTestInput& in) {
  VisualInertialInitializer init(o, in.calib);
  std::vector<window::FrameInput> frames;
  std::vector<inertial::ImageMotionFlag> flags;
  SearchRun r;
  for (std::size_t i = 0; i < in.frames.size() && !r.done; ++i) {
    frames.push_back(in.frames[i]);
    if (i > 0) {
      const auto flag = ImageMotion(frames[i - 1], frames[i], o.image_still_px);
      if (flag) flags.push_back(*flag);
    }
    const int before = init.two_view_tests();
    r.done = init.Advance(frames, in.imu, flags, i + 1 == in.frames.size());
    r.most_tests = std::max(r.most_tests, init.two_view_tests() - before);
    if (r.done) r.decided_at = static_cast<int>(i);
  }
  r.tests = init.two_view_tests();
  if (r.done) r.start = init.start();
  return r;
}

void ExpectSameStart(const VioStart& a, const VioStart& b) {
  EXPECT_EQ(a.method, b.method);
  EXPECT_EQ(a.first, b.first);
  EXPECT_EQ(a.second, b.second);
  EXPECT_EQ(a.candidates, b.candidates);
  EXPECT_LT((a.state_second.T_w_b.translation() - b.state_second.T_w_b.translation()).norm(),
            1e-12);
  EXPECT_LT((a.state_second.v_w - b.state_second.v_w).norm(), 1e-12);
}

TEST(StartSearchBudget, BoundsTheRansacsAFrameAndKeepsTheStart) {
  const VioTestInput in = Simulate(260);
  VisualInertialOdometryOptions o;
  const SearchRun open = RunSearch(o, in);
  o.init_pair_budget = 3;
  const SearchRun bounded = RunSearch(o, in);
  std::printf(
      "unbounded: %d RANSACs, at most %d a frame, start %d-%d decided at frame %d; budget 3: "
      "%d, at most %d, start %d-%d at frame %d\n",
      open.tests, open.most_tests, open.start.first, open.start.second, open.decided_at,
      bounded.tests, bounded.most_tests, bounded.start.first, bounded.start.second,
      bounded.decided_at);
  ASSERT_TRUE(open.done);
  ASSERT_TRUE(bounded.done);
  EXPECT_GT(open.most_tests, 3);  // the unbounded search's burst (7 here)
  EXPECT_LE(bounded.most_tests, 3);
  EXPECT_EQ(bounded.tests, open.tests);  // the same pairs, in the same order
  EXPECT_GE(bounded.decided_at, open.decided_at);
  ExpectSameStart(bounded.start, open.start);
  o.init_pair_budget = -1;
  EXPECT_THROW(o.Check(), std::invalid_argument);
}

// The rotated-parallax test refuses pairs without their RANSAC once the search has fallen behind,
// and at a budget that keeps the search near the newest frame it leaves the start as it was. (With
// a budget of 1 this corridor's search falls behind and the test refuses its start pair: the start
// becomes 43-153 after 279 RANSACs: docs/results/fisheye.md, session 22.)
TEST(StartSearchBudget, TheRotatedParallaxRefusesPairsWithoutTheirRansac) {
  const VioTestInput in = Simulate(260);
  VisualInertialOdometryOptions o;
  const SearchRun open = RunSearch(o, in);
  o.init_pair_budget = 3;
  o.init_pair_min_rotated_parallax_px = 7.5;
  const SearchRun tested = RunSearch(o, in);
  ASSERT_TRUE(tested.done);
  EXPECT_LE(tested.most_tests, 3);
  EXPECT_LE(tested.tests, open.tests);  // refused pairs run no RANSAC
  ExpectSameStart(tested.start, open.start);
  o.init_pair_min_rotated_parallax_px = -1.0;
  EXPECT_THROW(o.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace odometry
}  // namespace plucker
