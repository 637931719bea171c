// The dynamic start's extension by a turn (init_extend_min_rotation_deg,
// visual_inertial_initializer.h) on a simulated room: a start that has turned as much at its first
// alignment is that alignment, unchanged; else the run goes on to the first keyframe where the
// body has turned that much (the true rotation checked against the threshold on both sides);
// one that does not turn within init_extend_max_seconds keeps its first alignment.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "plucker/odometry/vio_test_utils.h"
#include "plucker/odometry/visual_inertial_initializer.h"
#include "plucker/sim/camera_observations.h"

namespace plucker {
namespace odometry {
namespace {

VioTestInput Simulate(int num_frames) {
  sim::CameraSimulationOptions o;
  o.scene.kind = sim::SceneKind::kRoom;
  o.num_frames = num_frames;
  o.seed = 3;
  return VioInputFromSimulation(sim::SimulateCamera(o), /*every_other_point=*/true);
}

struct InitRun {
  bool done = false;
  VioStart start;
  std::vector<VioInitEvent> events;
};

InitRun RunInitializer(const VisualInertialOdometryOptions& o, const VioTestInput& in) {
  VisualInertialInitializer init(o, in.calib);
  std::vector<window::FrameInput> frames;
  std::vector<inertial::ImageMotionFlag> flags;
  InitRun r;
  for (std::size_t i = 0; i < in.frames.size() && !r.done; ++i) {
    frames.push_back(in.frames[i]);
    if (i > 0) {
      const auto flag = ImageMotion(frames[i - 1], frames[i], o.image_still_px);
      if (flag) flags.push_back(*flag);
    }
    r.done = init.Advance(frames, in.imu, flags, i + 1 == in.frames.size());
  }
  if (r.done) r.start = init.start();
  r.events = init.events();
  return r;
}

// The largest true angle the body turns from the start's first keyframe to any later keyframe
// up to `last` (the second keyframe included), deg.
double TrueTurnDeg(const VioTestInput& in, const VioStart& s, int last) {
  std::vector<int> kf = s.candidates;
  kf.push_back(s.second);
  double most = 0.0;
  for (const int k : kf) {
    if (k > last) break;
    const Eigen::Quaterniond q =
        in.gt_T_w_b[kf.front()].rotation().conjugate() * in.gt_T_w_b[k].rotation();
    most = std::max(most, Eigen::AngleAxisd(q).angle() * 180.0 / M_PI);
  }
  return most;
}

bool HasExtensionEvent(const InitRun& r) {
  return std::any_of(r.events.begin(), r.events.end(),
                     [](const VioInitEvent& e) { return e.event == "extension"; });
}

TEST(StartExtension, WaitsForTheTurnAndOnlyThen) {
  const VioTestInput in = Simulate(200);
  VisualInertialOdometryOptions o;
  o.use_lines = false;
  o.init_max_keyframes = 80;
  o.init_extend_min_rotation_deg = 0.0;  // the first alignment (the default waits for 60 deg)
  o.init_extend_max_seconds = 0.0;
  const InitRun first = RunInitializer(o, in);
  ASSERT_TRUE(first.done);
  ASSERT_EQ(first.start.method, "dynamic");
  EXPECT_FALSE(HasExtensionEvent(first));
  const double turn0 = TrueTurnDeg(in, first.start, first.start.second);

  // Already turned that much: the first alignment stands, unchanged.
  o.init_extend_min_rotation_deg = 0.5 * turn0;
  const InitRun same = RunInitializer(o, in);
  ASSERT_TRUE(same.done);
  EXPECT_TRUE(HasExtensionEvent(same));
  EXPECT_EQ(same.start.second, first.start.second);
  EXPECT_EQ(same.start.candidates, first.start.candidates);
  EXPECT_EQ(same.start.state_second.v_w, first.start.state_second.v_w);

  // Not yet: aligned again at the first keyframe that has turned the threshold.
  const double threshold = turn0 + 15.0;
  o.init_extend_min_rotation_deg = threshold;
  const InitRun more = RunInitializer(o, in);
  ASSERT_TRUE(more.done);
  ASSERT_EQ(more.start.method, "dynamic");
  EXPECT_TRUE(HasExtensionEvent(more));
  EXPECT_EQ(more.start.candidates.front(), first.start.candidates.front());
  ASSERT_GT(more.start.second, first.start.second);
  ASSERT_LT(static_cast<int>(more.start.candidates.size()) + 1, o.init_max_keyframes);
  // The gyroscope at the alignment's bias against the truth: within 1 deg either side.
  EXPECT_GT(TrueTurnDeg(in, more.start, more.start.second), threshold - 1.0);
  EXPECT_LT(TrueTurnDeg(in, more.start, more.start.candidates.back()), threshold + 1.0);
  EXPECT_EQ(more.start.T_w_b.size(), static_cast<std::size_t>(more.start.second) + 1);

  // A turn that does not come within init_extend_max_seconds: the first alignment.
  o.init_extend_min_rotation_deg = 1e4;
  o.init_extend_max_seconds = 1.0;
  const InitRun never = RunInitializer(o, in);
  ASSERT_TRUE(never.done);
  EXPECT_TRUE(HasExtensionEvent(never));
  EXPECT_EQ(never.start.second, first.start.second);
  EXPECT_EQ(never.start.state_second.v_w, first.start.state_second.v_w);
}

}  // namespace
}  // namespace odometry
}  // namespace plucker
