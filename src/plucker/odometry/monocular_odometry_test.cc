#include "plucker/odometry/monocular_odometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "plucker/eval/ate.h"
#include "plucker/sim/camera_observations.h"

namespace plucker {
namespace odometry {
namespace {

using window::FrameInput;

sim::CameraSimulation Simulate(int frames) {
  sim::CameraSimulationOptions options;
  options.scene.kind = sim::SceneKind::kRoom;
  options.num_frames = frames;
  options.seed = 1;
  options.simulate_imu = false;
  return sim::SimulateCamera(options);
}

std::vector<FrameInput> Inputs(const sim::CameraSimulation& s) {
  std::vector<FrameInput> in(s.frame_times.size());
  for (std::size_t i = 0; i < in.size(); ++i) in[i].time = s.frame_times[i];
  for (const auto& p : s.points)
    if (p.point_id >= 0) in[p.frame].points.push_back(p);
  for (const auto& l : s.segments) in[l.frame].segments.push_back(l);
  return in;
}

// plucker vo's defaults on a features folder, the start's second view within `gap` frames.
MonocularOdometryOptions Options(int gap) {
  MonocularOdometryOptions o;
  o.start.two_view.min_common_tracks = 8;
  o.start.two_view.min_inliers = 8;
  o.start.max_init_gap = gap;
  return o;
}

struct VoRun {
  std::vector<MonocularFrameResult> online;
  std::vector<MonocularFrameRecord> refined;
  std::vector<MonocularMap> maps;
  MonocularSummary summary;
  std::string start_failure;
};

// Feeds frames [0, count) one at a time, then Finish().
VoRun Feed(const PinholeIntrinsics& K, const std::vector<FrameInput>& in, int count,
           const MonocularOdometryOptions& options) {
  MonocularOdometry vo(K, options);
  VoRun run;
  for (int i = 0; i < count; ++i) run.online.push_back(vo.AddFrame(in[i]));
  vo.Finish();
  run.refined = vo.Trajectory();
  run.maps = vo.Maps();
  run.summary = vo.Summary();
  run.start_failure = vo.StartFailure();
  return run;
}

bool SamePose(const SE3d& a, const SE3d& b) {
  return std::memcmp(a.translation().data(), b.translation().data(), 3 * sizeof(double)) == 0 &&
         std::memcmp(a.rotation().coeffs().data(), b.rotation().coeffs().data(),
                     4 * sizeof(double)) == 0;
}

double Ate(const sim::CameraSimulation& s, const std::vector<MonocularFrameRecord>& refined) {
  std::vector<SE3d> est;
  for (const auto& r : refined) est.push_back(r.T_w_c);
  eval::AteOptions ate;
  ate.align = eval::AlignmentMode::kSim3;
  return eval::ComputeAte(s.T_w_c_gt, est, ate).translation_m.rmse;
}

// The two-view start of a first view waits for its max_init_gap later frames; the frames
// before are buffered (no online pose) and localised against the map in the refined view.
TEST(MonocularOdometry, TwoViewStartWaitsForItsPairsThenTracks) {
  const sim::CameraSimulation s = Simulate(24);
  const std::vector<FrameInput> in = Inputs(s);
  MonocularOdometryOptions options = Options(6);
  options.start.multi_view_start = false;
  const VoRun run = Feed(s.rig.K, in, 24, options);
  ASSERT_EQ(run.maps.size(), 1u);
  EXPECT_EQ(run.maps[0].first, 0);
  EXPECT_GT(run.maps[0].second, 0);
  EXPECT_LE(run.maps[0].second, 6);
  EXPECT_FALSE(run.maps[0].chained_baseline);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(run.online[i].status, MonocularStatus::kInitializing) << i;
    EXPECT_FALSE(run.online[i].has_pose) << i;
  }
  EXPECT_EQ(run.online[6].status, MonocularStatus::kInitialized);
  EXPECT_TRUE(run.online[6].has_pose);
  for (int i = 7; i < 24; ++i) EXPECT_EQ(run.online[i].status, MonocularStatus::kTracking) << i;
  for (int i = 0; i < 24; ++i) EXPECT_TRUE(run.refined[i].has_pose) << i;
  EXPECT_EQ(run.summary.lost_frames, 0);
  const double ate = Ate(s, run.refined);
  std::printf("room 24 frames: start on %d-%d, ATE %.4f m (Sim(3))\n", run.maps[0].first,
              run.maps[0].second, ate);
  EXPECT_LT(ate, 0.05);
  // Pairs in order (plucker vo's image default): the first pair that passes starts at once.
  options.start.widest_init_pair = false;
  options.start.max_init_tries = 1;
  const VoRun first = Feed(s.rig.K, in, 24, options);
  ASSERT_EQ(first.maps.size(), 1u);
  const int b = first.maps[0].second;
  EXPECT_LT(b, run.maps[0].second);
  for (int i = 0; i < b; ++i) EXPECT_EQ(first.online[i].status, MonocularStatus::kInitializing);
  EXPECT_EQ(first.online[b].status, MonocularStatus::kInitialized);
  EXPECT_TRUE(first.online[b].has_pose);
}

// A camera standing still (12 copies of frame 0): no pair of the still frames gives a start (no
// parallax: the essential matrix has no inliers in front of both views), so the start waits
// (status initialising) until a first view whose pairs reach the moving frames; all still: no
// start, and the reason is given.
TEST(MonocularOdometry, StartWithTooLittleParallaxIsRefusedAndWaits) {
  const sim::CameraSimulation s = Simulate(30);
  std::vector<FrameInput> in = Inputs(s);
  std::vector<FrameInput> still;
  for (int i = 0; i < 12; ++i) {
    still.push_back(in[0]);
    still.back().time = 0.1 * i;
  }
  for (int i = 0; i < 18; ++i) {
    still.push_back(in[i]);
    still.back().time = 1.2 + 0.1 * i;
  }
  const VoRun run = Feed(s.rig.K, still, 30, Options(5));
  ASSERT_EQ(run.maps.size(), 1u);
  EXPECT_GE(run.maps[0].first, 7);  // first views 0-6 see still frames only
  EXPECT_GE(run.maps[0].second, 12);
  for (int i = 0; i < run.maps[0].first + 5; ++i)
    EXPECT_EQ(run.online[i].status, MonocularStatus::kInitializing) << i;
  const VoRun none = Feed(s.rig.K, still, 12, Options(5));
  EXPECT_TRUE(none.maps.empty());
  EXPECT_FALSE(none.start_failure.empty());
  std::printf("still start: first map %d-%d; all still: \"%s\"\n", run.maps[0].first,
              run.maps[0].second, none.start_failure.c_str());
}

// Frames 12-15 without observations: 3 lost frames, then a new start after them with the scale
// chained to the first map's speed; the trajectory stays within a few cm of the ground truth.
std::vector<FrameInput> WithGap(const std::vector<FrameInput>& in) {
  std::vector<FrameInput> gap = in;
  for (int i = 12; i <= 15; ++i) {
    gap[i].points.clear();
    gap[i].segments.clear();
  }
  return gap;
}

TEST(MonocularOdometry, LossThenRestartWithChainedScale) {
  const sim::CameraSimulation s = Simulate(30);
  const std::vector<FrameInput> in = WithGap(Inputs(s));
  const VoRun run = Feed(s.rig.K, in, 30, Options(5));
  ASSERT_EQ(run.maps.size(), 2u);
  EXPECT_EQ(run.summary.lost_frames, 3);
  EXPECT_EQ(run.maps[1].after_lost_frame, 14);
  EXPECT_TRUE(run.maps[1].chained_baseline);
  for (int i = 12; i <= 14; ++i) EXPECT_EQ(run.online[i].status, MonocularStatus::kLost) << i;
  EXPECT_EQ(run.online[15].status, MonocularStatus::kInitializing);
  int reinitialized = 0;
  for (const auto& r : run.online) reinitialized += r.status == MonocularStatus::kReinitialized;
  EXPECT_EQ(reinitialized, 1);
  std::printf("gap: second map %d-%d, chained baseline %.4f\n", run.maps[1].first,
              run.maps[1].second, *run.maps[1].chained_baseline);
}

// The result for frame k uses only the inputs up to k: runs on prefixes of the sequence give the
// same per-frame results, to the bit, as the whole run (start, loss and restart included).
TEST(MonocularOdometry, FrameByFrameEqualsTheWholeRun) {
  const sim::CameraSimulation s = Simulate(30);
  const std::vector<FrameInput> in = WithGap(Inputs(s));
  const VoRun whole = Feed(s.rig.K, in, 30, Options(5));
  for (int count : {4, 9, 14, 17, 23}) {
    const VoRun prefix = Feed(s.rig.K, in, count, Options(5));
    for (int i = 0; i < count; ++i) {
      const MonocularFrameResult &a = prefix.online[i], &b = whole.online[i];
      EXPECT_EQ(a.status, b.status) << count << " " << i;
      EXPECT_EQ(a.has_pose, b.has_pose) << count << " " << i;
      EXPECT_TRUE(SamePose(a.T_w_c, b.T_w_c)) << count << " " << i;
      EXPECT_EQ(a.window.has_value(), b.window.has_value()) << count << " " << i;
    }
  }
  // Frames given in one piece or one by one: the refined views agree (Finish on the same input).
  const VoRun again = Feed(s.rig.K, in, 30, Options(5));
  for (int i = 0; i < 30; ++i)
    EXPECT_TRUE(SamePose(again.refined[i].T_w_c, whole.refined[i].T_w_c));
}

// window.start_scale_sigma: the distance between the first window's two oldest keyframes stays
// at the start's value until the first marginalization (none in 30 frames with 40 keyframes);
// without it the solves after the start move it.
TEST(MonocularOdometry, StartScaleSigmaHoldsTheStartsScale) {
  const sim::CameraSimulation s = Simulate(30);
  const std::vector<FrameInput> in = Inputs(s);
  for (const double sigma : {0.0, 1e-6}) {
    MonocularOdometryOptions o = Options(5);
    o.window.window_size = 40;
    o.window.start_scale_sigma = sigma;
    MonocularOdometry vo(s.rig.K, o);
    for (const FrameInput& f : in) vo.AddFrame(f);
    vo.Finish();
    ASSERT_EQ(vo.Maps().size(), 1u);
    const std::vector<int>& kf = vo.Maps()[0].keyframes;
    ASSERT_GE(kf.size(), 2u);
    const auto& t = vo.Trajectory();
    const double d0 = (t[kf[1]].T_w_c.translation() - t[kf[0]].T_w_c.translation()).norm();
    const std::vector<SE3d> poses = vo.map()->KeyframePoses();
    ASSERT_GT(poses.size(), kf.size() + 2);  // keyframes after the start were solved
    const double d = (poses[1].translation() - poses[0].translation()).norm();
    ASSERT_GT(d0, 0.0);
    if (sigma > 0.0)
      EXPECT_NEAR(d / d0, 1.0, 1e-5) << "held";
    else
      EXPECT_GT(std::abs(d / d0 - 1.0), 1e-4) << "free";
  }
  window::SlidingWindowOptions bad;
  bad.start_scale_sigma = -1.0;
  EXPECT_THROW(window::SlidingWindowEstimator(s.rig.K, bad), std::invalid_argument);
}

TEST(MonocularOdometry, RejectsBadOptions) {
  MonocularOdometryOptions options;
  options.max_lost_frames = 0;
  EXPECT_THROW(MonocularOdometry(PinholeIntrinsics(), options), std::invalid_argument);
  options = MonocularOdometryOptions();
  options.start.max_init_gap = 0;
  EXPECT_THROW(MonocularOdometry(PinholeIntrinsics(), options), std::invalid_argument);
}

}  // namespace
}  // namespace odometry
}  // namespace plucker
