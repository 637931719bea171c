// Issue 26 part 2b: after a standing start, vision must start. A simulated corridor at 20 Hz
// whose body stands 1.25 s and then speeds up forward (seed 101: `plucker sim camera --scene
// corridor --rate 20 --seed 101 --standing-start 1.25`): forward motion down the corridor barely
// moves the points in the image, so the image test took the moving body for standing; the
// zero-motion updates clamped its velocity to zero, the IMU prediction went wrong and no landmark
// was ever triangulated (0 points in the window, 258 of 298 frames on the IMU alone, 10 m of
// error). This test on main 292d41d (its window_tracking.cc, window_keyframe_policy.cc): 0 window
// points, 0 tracked frames, 158 of 198 frames IMU-only, ATE 2.30 m; with the fix it passes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "plucker/eval/ate.h"
#include "plucker/odometry/vio_test_utils.h"
#include "plucker/odometry/visual_inertial_odometry.h"
#include "plucker/sim/camera_observations.h"

namespace plucker {
namespace odometry {
namespace {

TEST(VisualInertialOdometryStandingStart, VisionStartsAfterAStaticStartOnACorridor) {
  sim::CameraSimulationOptions o;
  o.scene.kind = sim::SceneKind::kCorridor;
  o.num_frames = 200;
  o.frame_rate_hz = 20.0;
  o.seed = 101;
  o.trajectory.standing_start_s = 1.25;
  const sim::CameraSimulation s = sim::SimulateCamera(o);
  const VioTestInput in = VioInputFromSimulation(s, /*every_other_point=*/false);
  VisualInertialOdometryOptions options;
  options.use_lines = false;
  VisualInertialOdometry vio(options, in.calib);
  int window_points = 0;
  FeedVio(vio, in, [&](VisualInertialOdometry&, const VioFrameResult& r) {
    if (r.window) window_points = r.window->window_points;
    return true;
  });
  EXPECT_EQ(vio.initialization().method, "static");
  const VioStatistics& st = vio.statistics();
  EXPECT_GT(window_points, 50);  // vision started and holds a map
  EXPECT_GT(st.tracked_frames, 120);
  EXPECT_LT(st.ImuOnlyShare(), 0.2) << st.imu_only_frames << " of " << st.window_frames;
  std::vector<SE3d> est, gt;
  for (const VioFrameRecord& r : vio.RefinedTrajectory()) {
    if (!r.T_w_b) continue;
    est.push_back(*r.T_w_b);
    gt.push_back(s.T_w_b_gt[r.frame]);
  }
  ASSERT_GT(est.size(), 190u);
  const eval::AteResult ate = eval::ComputeAte(gt, est, {eval::AlignmentMode::kPositionYaw});
  EXPECT_LT(ate.translation_m.rmse, 0.5);
}

// The static test's still span after a standing start at 20 Hz (seed 204 of the robustness
// table, `--scene corridor --rate 20 --standing-start 1.25`): the image motion between two 20 Hz
// frames stays under image_still_px during the smooth speed-up, so against the previous frame
// (image_still_span_s = 0, as before) the span ran to 2.0 s, 0.75 s into the motion, and its
// gravity was 2.1 deg off (the run drifted 22 m over 30 s); against the frame 0.1 s older the
// span ends 0.5 s earlier, its gravity 1.26 deg off (the run: 0.19 m).
struct StillSpan {
  double seconds = 0.0, up_error_deg = 180.0;
};

StillSpan StaticStartOnCorridor(double image_still_span_s) {
  sim::CameraSimulationOptions o;
  o.scene.kind = sim::SceneKind::kCorridor;
  o.num_frames = 60;
  o.frame_rate_hz = 20.0;
  o.seed = 204;
  o.trajectory.standing_start_s = 1.25;
  const sim::CameraSimulation s = sim::SimulateCamera(o);
  const VioTestInput in = VioInputFromSimulation(s, /*every_other_point=*/false);
  VisualInertialOdometryOptions options;
  options.use_lines = false;
  options.image_still_span_s = image_still_span_s;
  VisualInertialOdometry vio(options, in.calib);
  FeedVio(vio, in, [](VisualInertialOdometry& v, const VioFrameResult&) {
    return !v.initialization().done;
  });
  StillSpan span;
  for (const VioInitEvent& e : vio.initialization().events) {
    if (e.event != "static_test" || !e.still) continue;
    const Eigen::Vector3d up_gt = s.T_w_b_gt.front().RotationMatrix().transpose().col(2);
    span.seconds = e.still_seconds;
    span.up_error_deg = std::acos(std::min(1.0, up_gt.dot(e.up_b.normalized()))) * 180.0 / M_PI;
  }
  return span;
}

TEST(VisualInertialOdometryStandingStart, StillSpanEndsWhereTheMotionStartsAt20Hz) {
  const StillSpan before = StaticStartOnCorridor(0.0);  // against the previous frame
  EXPECT_GT(before.seconds, 1.5);                       // the old failure is reproduced
  EXPECT_GT(before.up_error_deg, 1.0);
  const StillSpan after = StaticStartOnCorridor(VisualInertialOdometryOptions().image_still_span_s);
  EXPECT_GE(after.seconds, 1.0);  // still a static start
  // Measured: 1.75 s and 1.26 deg (from 2.0 s, 2.1 deg): shorter, not yet at the 1.25 s stand
  // (the smooth speed-up's first 0.5 s stays under image_still_px over 0.1 s as well).
  EXPECT_LE(after.seconds, 1.75);
  EXPECT_LT(after.up_error_deg, 1.5);
  EXPECT_LT(after.up_error_deg, before.up_error_deg - 0.5);
}

}  // namespace
}  // namespace odometry
}  // namespace plucker
