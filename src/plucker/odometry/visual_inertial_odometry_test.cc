// The online visual-inertial odometry on simulated rooms: the dynamic start, the static start
// (a still period spliced before the motion), a start the gyroscope check refuses, the restart
// of the dynamic search, tracking lost and regained, an IMU gap among the start's keyframes, and
// frame-by-frame feeding against the IMU given all at once (nothing of the future is used).
#include "plucker/odometry/visual_inertial_odometry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "plucker/eval/ate.h"
#include "plucker/odometry/vio_test_utils.h"
#include "plucker/sim/camera_observations.h"

namespace plucker {
namespace odometry {
namespace {

using Input = VioTestInput;

Input Simulate(int num_frames, std::uint64_t seed = 1) {
  sim::CameraSimulationOptions o;
  o.scene.kind = sim::SceneKind::kRoom;
  o.num_frames = num_frames;
  o.seed = seed;
  return VioInputFromSimulation(sim::SimulateCamera(o), /*every_other_point=*/true);
}

VisualInertialOdometryOptions FastOptions() {
  VisualInertialOdometryOptions o;
  o.use_lines = false;
  return o;
}

struct VioRun {
  std::vector<VioFrameResult> results;
  std::vector<VioFrameRecord> refined;
  VioInitialization init;
};

// As a driver: the IMU up to each frame's time, then the frame (imu_first: all the IMU first).
VioRun Feed(const Input& in, const VisualInertialOdometryOptions& options, bool imu_first = false,
            int num_frames = -1) {
  VisualInertialOdometry vio(options, in.calib);
  VioRun run;
  const int n = num_frames < 0 ? static_cast<int>(in.frames.size()) : num_frames;
  std::size_t k = 0;
  if (imu_first)
    for (; k < in.imu.size(); ++k) vio.AddImu(in.imu[k]);
  for (int i = 0; i < n; ++i) {
    while (k < in.imu.size() && (k == 0 || in.imu[k - 1].t < in.frames[i].time))
      vio.AddImu(in.imu[k++]);
    run.results.push_back(vio.AddFrame(in.frames[i]));
  }
  if (num_frames < 0) run.results.push_back(vio.Finish());
  run.refined = vio.RefinedTrajectory();
  run.init = vio.initialization();
  return run;
}

bool Same(const std::optional<SE3d>& a, const std::optional<SE3d>& b) {
  if (a.has_value() != b.has_value()) return false;
  return !a ||
         (a->translation() == b->translation() && a->rotation().coeffs() == b->rotation().coeffs());
}

int StartFrame(const VioRun& run) {
  for (const VioFrameResult& r : run.results)
    if (!r.settled.empty()) return r.frame;
  return -1;
}

double AtePositionYaw(const VioRun& run, const Input& in) {
  std::vector<SE3d> gt, est;
  for (const VioFrameRecord& r : run.refined) {
    if (!r.T_w_b) continue;
    gt.push_back(in.gt_T_w_b[r.frame]);
    est.push_back(*r.T_w_b);
  }
  return eval::ComputeAte(gt, est, {eval::AlignmentMode::kPositionYaw}).translation_m.rmse;
}

TEST(VisualInertialOdometry, DynamicStartOnAMovingRoom) {
  const Input in = Simulate(60);
  const VioRun run = Feed(in, FastOptions());
  ASSERT_TRUE(run.init.done);
  EXPECT_EQ(run.init.method, "dynamic");
  const int start = StartFrame(run);
  ASSERT_GT(start, 0);
  EXPECT_EQ(start, run.init.second);  // the alignment's last keyframe is the current frame
  for (int i = 0; i < start; ++i) {
    EXPECT_EQ(run.results[i].status, VioStatus::kInitializing) << i;
    EXPECT_FALSE(run.results[i].T_w_b) << i;
  }
  EXPECT_EQ(run.results[start].settled.size(), static_cast<std::size_t>(start + 1));
  for (int i = start; i < 60; ++i) EXPECT_TRUE(run.results[i].T_w_b) << i;
  for (const VioFrameRecord& r : run.refined) EXPECT_TRUE(r.T_w_b) << r.frame;  // backfilled
  EXPECT_LT(AtePositionYaw(run, in), 0.15);
}

// The frame observer (vio --draw) sees every frame with a pose once, in order after the start,
// with the pose of the refined trajectory as the camera's and the frame's own observations.
TEST(VisualInertialOdometry, FrameObserverSeesEveryPosedFrameOnce) {
  const Input in = Simulate(60);
  VisualInertialOdometry vio(FastOptions(), in.calib);
  std::vector<int> seen;
  std::map<int, SE3d> T_w_c_seen;
  vio.SetFrameObserver([&](int i, const window::FrameInput& frame, const SE3d& T_w_c,
                           const window::SlidingWindowEstimator& map) {
    seen.push_back(i);
    T_w_c_seen[i] = T_w_c;
    EXPECT_EQ(frame.time, in.frames[i].time) << i;
    EXPECT_EQ(frame.points.size(), in.frames[i].points.size()) << i;
    EXPECT_FALSE(map.Points().empty()) << i;
  });
  std::size_t k = 0;
  for (const window::FrameInput& frame : in.frames) {
    while (k < in.imu.size() && (k == 0 || in.imu[k - 1].t < frame.time)) vio.AddImu(in.imu[k++]);
    vio.AddFrame(frame);
  }
  vio.Finish();
  std::vector<int> posed;
  for (const VioFrameRecord& r : vio.RefinedTrajectory())
    if (r.T_w_b) posed.push_back(r.frame);
  ASSERT_EQ(posed.size(), in.frames.size());
  EXPECT_EQ(seen, posed);  // once each, in order
  for (const VioFrameRecord& r : vio.RefinedTrajectory()) {
    const SE3d T_w_c = *r.T_w_b * in.calib.T_b_c;
    EXPECT_TRUE(T_w_c_seen.at(r.frame).translation().isApprox(T_w_c.translation(), 1e-12))
        << r.frame;
  }
}

// A window smaller than the alignment's keyframes starts on the newest of them: the reported
// first keyframe and its state are the window's (the state was the alignment's first keyframe's).
TEST(VisualInertialOdometry, DynamicStartReportsTheWindowsFirstKeyframeState) {
  const Input in = Simulate(60);
  VisualInertialOdometryOptions o = FastOptions();
  o.window = 4;
  const VioRun run = Feed(in, o);
  ASSERT_TRUE(run.init.done);
  ASSERT_EQ(run.init.method, "dynamic");
  ASSERT_GT(run.init.first, 0);
  EXPECT_NEAR(run.init.state_first.t, in.frames[run.init.first].time, 1e-9);
  ASSERT_TRUE(run.refined[run.init.first].keyframe);
  ASSERT_TRUE(run.refined[run.init.first].T_w_b);
  // The alignment's pose of that keyframe, before the window's first solve moved it.
  EXPECT_LT(
      (run.init.state_first.T_w_b.translation() - run.refined[run.init.first].T_w_b->translation())
          .norm(),
      0.05);
}

// The result of frame k depends on the inputs up to frame k only: the IMU given all at once,
// and a run stopped at frame k, give the same per-frame results bit for bit.
TEST(VisualInertialOdometry, FrameByFrameEqualsBatch) {
  const Input in = Simulate(60);
  const VioRun online = Feed(in, FastOptions());
  const VioRun batch = Feed(in, FastOptions(), /*imu_first=*/true);
  const int start = StartFrame(online);
  ASSERT_GT(start, 0);
  const VioRun prefix = Feed(in, FastOptions(), false, start + 5);
  ASSERT_EQ(online.results.size(), batch.results.size());
  for (std::size_t i = 0; i < online.results.size(); ++i) {
    EXPECT_EQ(online.results[i].status, batch.results[i].status) << i;
    EXPECT_TRUE(Same(online.results[i].T_w_b, batch.results[i].T_w_b)) << i;
    if (i < prefix.results.size()) {
      EXPECT_EQ(online.results[i].status, prefix.results[i].status) << i;
      EXPECT_TRUE(Same(online.results[i].T_w_b, prefix.results[i].T_w_b)) << i;
    }
  }
  ASSERT_EQ(online.refined.size(), batch.refined.size());
  for (std::size_t i = 0; i < online.refined.size(); ++i)
    EXPECT_TRUE(Same(online.refined[i].T_w_b, batch.refined[i].T_w_b)) << i;
}

// A still period before the motion: the IMU at rest at the first pose, the first frame's
// observations repeated; then the simulated motion, later by the still period.
Input StillThenMoving(int still_frames, int moving_frames) {
  const Input moving = Simulate(moving_frames);
  Input in = moving;
  const double dt = moving.frames[1].time - moving.frames[0].time;
  const double shift = still_frames * dt;
  in.frames.clear();
  in.imu.clear();
  in.gt_T_w_b.clear();
  const Eigen::Vector3d f_b = moving.gt_T_w_b[0].rotation().conjugate() *
                              Eigen::Vector3d(0.0, 0.0, moving.calib.gravity_magnitude);
  for (double t = moving.imu.front().t; t < moving.frames[0].time + shift - 1e-9; t += 0.005) {
    sensor::ImuSample s;
    s.t = t;
    s.accel = f_b + moving.imu.front().accel_bias;
    s.gyro = moving.imu.front().gyro_bias;
    in.imu.push_back(s);
  }
  for (int i = 0; i < still_frames; ++i) {
    window::FrameInput f = moving.frames[0];
    f.time = moving.frames[0].time + i * dt;
    in.frames.push_back(f);
    in.gt_T_w_b.push_back(moving.gt_T_w_b[0]);
  }
  for (sensor::ImuSample s : moving.imu) {
    s.t += shift;
    if (s.t > in.imu.back().t) in.imu.push_back(s);
  }
  for (std::size_t i = 1; i < moving.frames.size(); ++i) {
    window::FrameInput f = moving.frames[i];
    f.time += shift;
    in.frames.push_back(f);
    in.gt_T_w_b.push_back(moving.gt_T_w_b[i]);
  }
  return in;
}

TEST(VisualInertialOdometry, StaticStartDecidedWhenTheMotionStarts) {
  const Input in = StillThenMoving(40, 30);
  const VioRun run = Feed(in, FastOptions());
  ASSERT_TRUE(run.init.done);
  EXPECT_EQ(run.init.method, "static");
  EXPECT_EQ(run.init.first, 0);
  EXPECT_EQ(run.init.second, 1);
  const int start = StartFrame(run);
  EXPECT_GE(start, 40);  // not before the images move
  EXPECT_LT(start, 50);
  ASSERT_FALSE(run.init.events.empty());
  EXPECT_TRUE(run.init.events.front().still);
  EXPECT_GT(run.init.events.front().still_seconds, 1.0);
  for (int i = 0; i < start; ++i) EXPECT_FALSE(run.results[i].T_w_b) << i;
  const std::vector<VioFrameRecord>& settled = run.results[start].settled;
  ASSERT_EQ(settled.size(), static_cast<std::size_t>(start + 1));
  for (int i = 2; i < 40; ++i) {  // the window's zero-motion update while standing
    ASSERT_TRUE(settled[i].window) << i;
    EXPECT_TRUE(settled[i].window->stationary) << i;
  }
  for (const VioFrameRecord& r : run.refined) EXPECT_TRUE(r.T_w_b) << r.frame;
}

TEST(VisualInertialOdometry, StillThroughoutStartsStaticAtTheEnd) {
  const Input in = StillThenMoving(30, 2);
  Input still = in;
  still.frames.resize(30);
  const VioRun run = Feed(still, FastOptions());
  EXPECT_EQ(run.init.method, "static");
  EXPECT_EQ(StartFrame(run), 29);  // Finish: the frames so far
  EXPECT_EQ(run.results.back().settled.size(), 30u);
}

// The gyroscope disagrees with every two-view rotation (a 0.5 rad/s bias about the camera's
// optical axis): no vision-only run starts; with the check loosened the same data starts one.
TEST(VisualInertialOdometry, GyroscopeCheckRefusesTheTwoViewStart) {
  Input in = Simulate(16);
  const Eigen::Vector3d axis_b = in.calib.T_b_c.rotation() * Eigen::Vector3d::UnitZ();
  for (sensor::ImuSample& s : in.imu) s.gyro += 0.5 * axis_b;
  const VioRun refused = Feed(in, FastOptions());
  EXPECT_FALSE(refused.init.done);
  EXPECT_EQ(refused.results.back().status, VioStatus::kFailed);
  for (const VioInitEvent& e : refused.init.events)
    EXPECT_TRUE(e.event == "static_test") << e.event;  // no run: no wait/alignment/restart
  VisualInertialOdometryOptions loose = FastOptions();
  loose.init_max_rotation_disagreement_deg = 180.0;
  const VioRun accepted = Feed(in, loose);
  const bool ran = std::any_of(accepted.init.events.begin(), accepted.init.events.end(),
                               [](const VioInitEvent& e) { return e.event != "static_test"; });
  EXPECT_TRUE(ran);
}

// A run that cannot align (the excitation demanded is out of reach) restarts from a later
// start frame, and the input ends without a start: kFailed with the message.
TEST(VisualInertialOdometry, DynamicSearchRestarts) {
  const Input in = Simulate(60);
  VisualInertialOdometryOptions o = FastOptions();
  o.init_min_excitation = 1e9;
  o.init_max_keyframes = 12;
  const VioRun run = Feed(in, o);
  EXPECT_FALSE(run.init.done);
  const int restarts =
      static_cast<int>(std::count_if(run.init.events.begin(), run.init.events.end(),
                                     [](const VioInitEvent& e) { return e.event == "restart"; }));
  EXPECT_GE(restarts, 1);
  EXPECT_EQ(run.results.back().status, VioStatus::kFailed);
  EXPECT_NE(run.results.back().message.find("cannot initialise"), std::string::npos);
}

// Frames without observations after the start: the IMU prediction (kImuOnly), then tracking
// resumes when the observations come back.
TEST(VisualInertialOdometry, TrackingLostAndRegained) {
  Input in = Simulate(60);
  const VioRun clean = Feed(in, FastOptions());
  const int start = StartFrame(clean);
  ASSERT_GT(start, 0);
  ASSERT_LT(start + 10, 60);
  const int lost_from = start + 2, lost_to = start + 4;
  for (int i = lost_from; i <= lost_to; ++i) in.frames[i].points.clear();
  const VioRun run = Feed(in, FastOptions());
  for (int i = lost_from; i <= lost_to; ++i) {
    EXPECT_EQ(run.results[i].status, VioStatus::kImuOnly) << i;
    EXPECT_TRUE(run.results[i].T_w_b) << i;
  }
  int tracked_after = 0;
  for (int i = lost_to + 1; i < 60; ++i)
    tracked_after += run.results[i].status == VioStatus::kTracking;
  EXPECT_GT(tracked_after, 0);
  EXPECT_LT(AtePositionYaw(run, in), 0.3);
}

TEST(VisualInertialOdometry, RejectsInvalidOptionsAndInputs) {
  VisualInertialOdometryOptions o;
  o.window = 1;
  EXPECT_FALSE(o.Problem().empty());
  const Input in = Simulate(5);
  EXPECT_THROW(VisualInertialOdometry(o, in.calib), std::invalid_argument);
  VisualInertialOdometry vio(FastOptions(), in.calib);
  vio.AddImu(in.imu[1]);
  EXPECT_THROW(vio.AddImu(in.imu[0]), std::invalid_argument);
  vio.AddFrame(in.frames[1]);
  EXPECT_THROW(vio.AddFrame(in.frames[0]), std::invalid_argument);
  EXPECT_THROW(vio.AddImage(10.0, cv::Mat()), std::invalid_argument);
}

// line_sigma_scale: the window's (and so the start's) line sigma is the pixel sigma times it, the
// point sigma stays; not positive or not finite is refused. keep_marginalized_lines reaches the
// window.
TEST(VisualInertialOdometry, LineSigmaScaleWeighsTheLinesOnly) {
  VisualInertialOdometryOptions o;
  VisualInertialCalibration calib;
  calib.pixel_sigma = 1.5;
  EXPECT_DOUBLE_EQ(WindowOptions(o, calib).line_sigma_px, 1.5);
  o.line_sigma_scale = 0.6;
  const window::SlidingWindowOptions w = WindowOptions(o, calib);
  EXPECT_DOUBLE_EQ(w.point_sigma_px, 1.5);
  EXPECT_DOUBLE_EQ(w.line_sigma_px, 0.9);
  EXPECT_TRUE(w.keep_marginalized_lines);
  o.keep_marginalized_lines = false;
  EXPECT_FALSE(WindowOptions(o, calib).keep_marginalized_lines);
  EXPECT_TRUE(o.Problem().empty());
  for (const double bad : {0.0, -1.0, std::numeric_limits<double>::infinity()}) {
    o.line_sigma_scale = bad;
    EXPECT_FALSE(o.Problem().empty()) << bad;
  }
}

double AlignmentScale(const VioRun& run) {
  for (const VioInitEvent& e : run.init.events)
    if (e.event == "alignment") return e.scale;
  return 0.0;
}

// An IMU gap of 0.4 s among the dynamic start's keyframes is bridged in the alignment as in the
// window (InertialOptions::imu_gap_s): its preintegration is not believed as if measured. Read
// as measured (the interpolated readings' covariance), the same gap gave a scale 15 % short
// (0.2905 against 0.3437) and an ATE of 0.116 m against 0.044 m; bridged 1 % and 0.061 m.
TEST(VisualInertialOdometry, DynamicStartBridgesAnImuGap) {
  const Input in = Simulate(60);
  Input gapped = in;
  const double t0 = in.frames[12].time + 0.013;
  gapped.imu.clear();
  for (const sensor::ImuSample& s : in.imu)
    if (s.t < t0 || s.t > t0 + 0.4) gapped.imu.push_back(s);
  const VioRun whole = Feed(in, FastOptions()), with_gap = Feed(gapped, FastOptions());
  ASSERT_TRUE(whole.init.done);
  ASSERT_TRUE(with_gap.init.done);
  ASSERT_EQ(with_gap.init.method, "dynamic");
  ASSERT_LT(with_gap.init.first, 12);  // the gap is among the alignment's keyframes
  ASSERT_GT(with_gap.init.second, 16);
  EXPECT_NEAR(AlignmentScale(with_gap) / AlignmentScale(whole), 1.0, 0.03);
  EXPECT_LT(AtePositionYaw(with_gap, in), 0.08);
}

}  // namespace
}  // namespace odometry
}  // namespace plucker
