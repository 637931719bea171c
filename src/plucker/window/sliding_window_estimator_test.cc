#include "plucker/window/sliding_window_estimator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include "plucker/eval/ate.h"
#include "plucker/sim/camera_observations.h"

namespace plucker {
namespace window {
namespace {

struct WindowRun {
  std::vector<SE3d> gt, est;
  double ate_m = 0.0;
  int keyframes = 0;
  int marginalized = 0;
  int failed_marginalizations = 0;
  int lost = 0;
  int line_obs_dropped = 0;
  int line_obs_held = 0;
  int retained_line_obs_dropped = 0;  // of retained poses beyond max_retained_poses
  int max_retained_poses = 0;
  int max_prior_lines = 0;
  int point_obs_dropped = 0;
  int marginalized_landmarks = 0;
  int max_prior_rank = 0;
  double mean_nees = 0.0;
  int nees_count = 0;
  bool initialized = false;
};

sim::CameraSimulation Simulate(sim::SceneKind kind, int frames, std::uint64_t seed) {
  sim::CameraSimulationOptions options;
  options.scene.kind = kind;
  options.num_frames = frames;
  options.seed = seed;
  options.simulate_imu = false;
  return sim::SimulateCamera(options);
}

// The frames of a simulation as window input; point tracks kept when id % point_stride == 0.
std::vector<FrameInput> Inputs(const sim::CameraSimulation& s, int point_stride) {
  std::vector<FrameInput> in(s.frame_times.size());
  for (std::size_t i = 0; i < in.size(); ++i) in[i].time = s.frame_times[i];
  for (const auto& p : s.points)
    if (p.point_id >= 0 && p.point_id % point_stride == 0) in[p.frame].points.push_back(p);
  for (const auto& l : s.segments) in[l.frame].segments.push_back(l);
  return in;
}

// Runs the window from ground-truth poses of frames 0 and `second` (a test may; the CLI may not),
// frames in between localized.
WindowRun RunWindow(const sim::CameraSimulation& s, const std::vector<FrameInput>& in,
                    const SlidingWindowOptions& options, int second = 3, bool nees = false) {
  WindowRun run;
  SlidingWindowEstimator estimator(s.rig.K, options);
  const InitializationResult init =
      estimator.Initialize(in[0], s.T_w_c_gt[0], in[second], s.T_w_c_gt[second]);
  run.initialized = init.ok;
  if (!init.ok) return run;
  run.est.push_back(init.T_w_a);
  for (int i = 1; i < second; ++i) {
    run.est.push_back(estimator.Localize(in[i], init.T_w_a).value_or(init.T_w_a));
  }
  run.est.push_back(init.T_w_b);
  double nees_sum = 0.0;
  for (std::size_t i = second + 1; i < in.size(); ++i) {
    const WindowFrameResult r = estimator.AddFrame(in[i]);
    run.est.push_back(r.T_w_c);
    run.keyframes += r.keyframe;
    run.marginalized += r.marginalized_keyframes;
    run.failed_marginalizations += r.marginalization_failed;
    run.lost += !r.ok;
    run.line_obs_dropped += r.dropped_line_observations;
    run.line_obs_held += r.held_line_observations;
    run.retained_line_obs_dropped += r.dropped_retained_line_observations;
    run.max_retained_poses = std::max(run.max_retained_poses, r.retained_poses);
    run.max_prior_lines = std::max(run.max_prior_lines, r.prior_lines);
    run.point_obs_dropped += r.dropped_point_observations;
    run.marginalized_landmarks += r.marginalized_landmarks;
    run.max_prior_rank = std::max(run.max_prior_rank, r.prior_rank);
    if (nees && r.keyframe) {
      const auto cov = estimator.NewestPoseCovariance();
      if (cov) {
        // Error in the PoseManifold tangent (rotation angle in [0, pi]).
        const Eigen::AngleAxisd aa(s.T_w_c_gt[i].RotationMatrix().transpose() *
                                   r.T_w_c.RotationMatrix());
        Vector6d e;
        e << aa.angle() * aa.axis(), r.T_w_c.translation() - s.T_w_c_gt[i].translation();
        nees_sum += e.dot(cov->ldlt().solve(e));
        ++run.nees_count;
      }
    }
  }
  run.gt = s.T_w_c_gt;
  if (run.nees_count > 0) run.mean_nees = nees_sum / run.nees_count;
  eval::AteOptions ate;
  ate.align = eval::AlignmentMode::kSim3;
  run.ate_m = eval::ComputeAte(run.gt, run.est, ate).translation_m.rmse;
  return run;
}

TEST(SlidingWindowEstimator, RecoversPosesOnASimulatedRoom) {
  const sim::CameraSimulation s = Simulate(sim::SceneKind::kRoom, 40, 1);
  SlidingWindowOptions options;
  const WindowRun run = RunWindow(s, Inputs(s, 1), options);
  ASSERT_TRUE(run.initialized);
  std::printf(
      "room 40 frames, all points + lines: ATE %.4f m, %d keyframes, %d marginalized, %d lost\n",
      run.ate_m, run.keyframes, run.marginalized, run.lost);
  ASSERT_EQ(run.est.size(), s.T_w_c_gt.size());
  EXPECT_GT(run.keyframes, 5);
  EXPECT_GT(run.marginalized, 0);
  EXPECT_EQ(run.failed_marginalizations, 0);
  EXPECT_EQ(run.lost, 0);
  EXPECT_LT(run.ate_m, 0.05);
}

// The multi-keyframe start (plucker vo's): a two-view start on frames 0 and 15 of the
// scarce-point room (ground-truth poses), frames 5 and 10 localised against it, then one solve of
// all four with their points and lines: the middle two end closer to the ground truth than
// localised (0.38 / 1.00 deg before, 0.23 / 0.73 after), all within 1 deg and 6 cm (the first
// pose is held, the scale free), and the window runs on from them.
TEST(SlidingWindowEstimator, InitializeOnSeveralKeyframesSolvesThemAll) {
  const sim::CameraSimulation s = Simulate(sim::SceneKind::kRoom, 26, 1);
  const std::vector<FrameInput> in = Inputs(s, 10);
  const std::vector<int> ids = {0, 5, 10, 15};
  SlidingWindowEstimator two_view(s.rig.K, SlidingWindowOptions{});
  ASSERT_TRUE(two_view.Initialize(in[0], s.T_w_c_gt[0], in[15], s.T_w_c_gt[15]).ok);
  std::vector<FrameInput> frames;
  std::vector<SE3d> poses;
  for (int k : ids) {
    frames.push_back(in[k]);
    const std::optional<SE3d> T =
        k == 0 || k == 15 ? s.T_w_c_gt[k] : two_view.Localize(in[k], s.T_w_c_gt[0]);
    ASSERT_TRUE(T.has_value()) << k;
    poses.push_back(*T);
  }
  SlidingWindowEstimator estimator(s.rig.K, SlidingWindowOptions{});
  const InitializationResult init = estimator.Initialize(frames, poses);
  std::printf("start on 4 keyframes: %d points, %d lines, %d residual blocks, cost %.1f\n",
              init.points, init.lines, init.residuals, init.final_cost);
  ASSERT_TRUE(init.ok);
  EXPECT_GT(init.points, 5);
  EXPECT_GT(init.lines, 10);
  EXPECT_GT(init.residuals, 100);
  EXPECT_GT(init.final_cost, 0.0);
  const std::vector<SE3d> solved = estimator.KeyframePoses();
  ASSERT_EQ(solved.size(), ids.size());
  const auto error = [&](int k, const SE3d& T) {
    const SE3d e = s.T_w_c_gt[k].Inverse() * T;
    return std::make_pair(Eigen::AngleAxisd(e.RotationMatrix()).angle() * 180.0 / M_PI,
                          e.translation().norm());
  };
  double localized_deg = 0.0, solved_deg = 0.0;  // of the middle two
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const auto [d0, m0] = error(ids[k], poses[k]);
    const auto [d1, m1] = error(ids[k], solved[k]);
    std::printf("keyframe %d: from %.3f deg, %.4f m to %.3f deg, %.4f m from the ground truth\n",
                ids[k], d0, m0, d1, m1);
    EXPECT_LT(d1, 1.0) << ids[k];
    EXPECT_LT(m1, 0.06) << ids[k];
    if (k == 1 || k == 2) localized_deg += d0, solved_deg += d1;
  }
  EXPECT_LT(solved_deg, localized_deg);
  int tracked = 0;
  for (int i = 16; i < 26; ++i) tracked += estimator.AddFrame(in[i]).ok;
  EXPECT_EQ(tracked, 10);
  // Sizes that differ, fewer than two frames, more than the window: refused.
  EXPECT_THROW(estimator.Initialize(frames, {poses[0]}), std::invalid_argument);
  EXPECT_THROW(estimator.Initialize({frames[0]}, {poses[0]}), std::invalid_argument);
  SlidingWindowOptions small;
  small.window_size = 3;
  SlidingWindowEstimator too_small(s.rig.K, small);
  EXPECT_THROW(too_small.Initialize(frames, poses), std::invalid_argument);
}

// One seed, lines kept (`keep`) against dropped at marginalization, on the same simulation and
// the same start: ground-truth poses of frame 0 and of the first frame from 3 that starts.
struct KeptAndDropped {
  WindowRun kept, dropped;
};
KeptAndDropped RunKeptAndDropped(sim::SceneKind kind, std::uint64_t seed, int point_stride,
                                 const SlidingWindowOptions& keep, int last_second,
                                 int frames = 100) {
  const sim::CameraSimulation s = Simulate(kind, frames, seed);
  const std::vector<FrameInput> in = Inputs(s, point_stride);
  SlidingWindowOptions drop = keep;
  drop.keep_marginalized_lines = false;
  int second = 3;
  KeptAndDropped r{RunWindow(s, in, keep, second), {}};
  while (!r.kept.initialized && second < last_second) r.kept = RunWindow(s, in, keep, ++second);
  r.dropped = RunWindow(s, in, drop, second);
  return r;
}

// Keeping the line observations of the marginalized keyframe against dropping them (PL-VIO), with
// scarce points, 100 frames, seeds 1-3, the same input for both. Kept (the defaults): k0's pose
// stays in the state while lines it observed do (retain_line_observer_poses), and no line ever
// becomes a block of the prior (a retained pose beyond max_retained_poses drops its observations
// of lines that stay). Room: one point track in ten, window 10, 100 frames. Corridor: one in
// forty, window 5 (at window 10 the corridor's kept/dropped differences are a few per cent,
// within the seed noise of 3 seeds; 18 seeds: kept better on 14, docs/vo.md), 50 frames (60 took
// about a minute under the sanitizer; at 40 seed 3 marginalizes too little to compare). Before
// (lines into the prior at once) kept lost on all three rooms (0.0756 / 0.0438 / 0.0794 m against
// 0.0622 / 0.0372 / 0.0654).
void ExpectKeptBeatsDropped(sim::SceneKind kind, int point_stride, int window_size, int frames) {
  const char* scene = kind == sim::SceneKind::kRoom ? "room" : "corridor";
  double kept_sum = 0.0, dropped_sum = 0.0;
  int kept_wins = 0;
  SlidingWindowOptions keep;
  keep.window_size = window_size;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const auto [kept, dropped] = RunKeptAndDropped(kind, seed, point_stride, keep, 30, frames);
    ASSERT_TRUE(kept.initialized && dropped.initialized) << scene << " seed " << seed;
    std::printf(
        "%s seed %d, scarce points, %d frames, window %d: ATE lines kept %.4f m (%d held, %d "
        "dropped "
        "beyond the retained poses, at most %d retained), dropped %.4f m (%d line observations "
        "dropped)\n",
        scene, static_cast<int>(seed), frames, window_size, kept.ate_m, kept.line_obs_held,
        kept.retained_line_obs_dropped, kept.max_retained_poses, dropped.ate_m,
        dropped.line_obs_dropped);
    EXPECT_EQ(kept.line_obs_dropped, 0);
    EXPECT_GT(kept.line_obs_held, 3 * frames);
    EXPECT_GT(kept.max_retained_poses, 0);
    EXPECT_EQ(kept.max_prior_lines, 0);  // no line is a block of the prior
    EXPECT_EQ(dropped.line_obs_held, 0);
    EXPECT_EQ(dropped.max_retained_poses, 0);
    EXPECT_GT(dropped.line_obs_dropped, 3 * frames);
    EXPECT_GT(kept.marginalized, 10);
    kept_sum += kept.ate_m;
    dropped_sum += dropped.ate_m;
    kept_wins += kept.ate_m < dropped.ate_m;
  }
  std::printf("%s, mean ATE over 3 seeds: lines kept %.4f m, dropped %.4f m; kept better on %d\n",
              scene, kept_sum / 3, dropped_sum / 3, kept_wins);
  EXPECT_LT(kept_sum, dropped_sum);
  EXPECT_GE(kept_wins, 2);
}

TEST(SlidingWindowEstimator, MarginalizationWithLinesKeptBeatsDropped) {
  ExpectKeptBeatsDropped(sim::SceneKind::kRoom, 10, 10, 100);
}

TEST(SlidingWindowEstimator, MarginalizationWithLinesKeptBeatsDroppedInTheCorridor) {
  ExpectKeptBeatsDropped(sim::SceneKind::kCorridor, 40, 5, 50);
}

// Two-sided sign test: the probability of a split at least as uneven as `wins` of `n` under
// p = 1/2.
double SignTestP(int wins, int n) {
  double p = 0.0;
  for (int i = 0; i <= n; ++i) {
    if (std::abs(2 * i - n) < std::abs(2 * wins - n)) continue;
    p += std::exp(std::lgamma(n + 1.0) - std::lgamma(i + 1.0) - std::lgamma(n - i + 1.0) -
                  n * std::log(2.0));
  }
  return std::min(p, 1.0);
}

// The window-protocol table of docs/vo.md (seeds 1-20, paired: the same simulation and start
// for kept and dropped; the variants of k0's line observations; room and corridor, window 10 and
// 100 frames, and for the last two variants also 200 frames and the corridor at window 5). Too
// slow for the suite (minutes): run it with
//   build/dev/src/plucker/window/window_sliding_window_estimator_test
//     --gtest_also_run_disabled_tests --gtest_filter='*KeptAgainstDroppedOverTwentySeeds'
TEST(SlidingWindowEstimator, DISABLED_KeptAgainstDroppedOverTwentySeeds) {
  SlidingWindowOptions in_prior, overflow_into_prior, now;
  in_prior.retain_line_observer_poses = false;
  overflow_into_prior.max_retained_poses = 10;
  overflow_into_prior.retained_overflow_into_prior = true;
  struct Row {
    const char* name;
    SlidingWindowOptions options;
    sim::SceneKind kind;
    int window, frames;
  };
  const auto room = sim::SceneKind::kRoom, corridor = sim::SceneKind::kCorridor;
  std::vector<Row> rows;
  for (const auto& [name, options] :
       {std::pair<const char*, SlidingWindowOptions>{"lines into the prior at once", in_prior},
        {"retained, overflow into the prior", overflow_into_prior},
        {"retained, no line in the prior", now}}) {
    rows.push_back({name, options, room, 10, 100});
    rows.push_back({name, options, corridor, 10, 100});
  }
  for (const auto& [name, options] : {std::pair<const char*, SlidingWindowOptions>{
                                          "retained, overflow into the prior", overflow_into_prior},
                                      {"retained, no line in the prior", now}}) {
    rows.push_back({name, options, room, 10, 200});
    rows.push_back({name, options, corridor, 10, 200});
    rows.push_back({name, options, corridor, 5, 100});
  }
  int runs = 0;
  for (Row row : rows) {
    row.options.window_size = row.window;
    std::vector<double> diff;  // dropped - kept, per seed that starts
    double kept_sum = 0.0, dropped_sum = 0.0;
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
      const int stride = row.kind == room ? 10 : 40;
      const auto [kept, dropped] =
          RunKeptAndDropped(row.kind, seed, stride, row.options, 30, row.frames);
      if (!kept.initialized || !dropped.initialized) continue;
      kept_sum += kept.ate_m;
      dropped_sum += dropped.ate_m;
      diff.push_back(dropped.ate_m - kept.ate_m);
    }
    const int n = static_cast<int>(diff.size());
    runs += n;
    if (n < 2) continue;
    const int wins =
        static_cast<int>(std::count_if(diff.begin(), diff.end(), [](double d) { return d > 0.0; }));
    double mean = 0.0, var = 0.0;
    for (double d : diff) mean += d / n;
    for (double d : diff) var += (d - mean) * (d - mean) / (n - 1);
    std::printf(
        "%-34s %-8s w%-2d %3d frames %2d started: kept %.4f / dropped %.4f m, kept better on %2d "
        "(sign test p %.3f), mean dropped - kept %+.4f m (paired t %+.2f)\n",
        row.name, row.kind == room ? "room" : "corridor", row.window, row.frames, n, kept_sum / n,
        dropped_sum / n, wins, SignTestP(wins, n), mean, mean / std::sqrt(var / n));
    std::fflush(stdout);
  }
  EXPECT_GT(runs, 12 * 15);  // most of the 12 x 20 (row, seed) runs start
}

// Every frame gets an absolute pose prior drawn from its own distribution around the ground
// truth (2 deg, 0.10 m; seed 7): a stand-in for what fixes the gauge and scale.
std::vector<FrameInput> WithNoisyPosePriors(const sim::CameraSimulation& s,
                                            std::vector<FrameInput> in) {
  const double sigma_rot = 2.0 * M_PI / 180.0, sigma_t = 0.10;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  Eigen::Matrix<double, 6, 6> S = Eigen::Matrix<double, 6, 6>::Identity();
  S.topLeftCorner<3, 3>() /= sigma_rot;
  S.bottomRightCorner<3, 3>() /= sigma_t;
  for (std::size_t i = 0; i < in.size(); ++i) {
    Vector6d d;
    for (int k = 0; k < 6; ++k) d(k) = normal(rng) * (k < 3 ? sigma_rot : sigma_t);
    in[i].T_w_c_prior = s.T_w_c_gt[i].Plus(d);
    in[i].prior_sqrt_information = S;
  }
  return in;
}

// NEES of the newest keyframe pose: every frame carries a noisy absolute pose prior (a stand-in
// for the IMU and gravity that fix the gauge and the scale monocular vision cannot), drawn from
// the prior's own distribution, so the window's covariance of the newest pose is defined; the
// normalized estimation error squared e^T P^-1 e (6 degrees of freedom) is reported.
TEST(SlidingWindowEstimator, NeesOfTheNewestPoseIsInASaneBand) {
  const sim::CameraSimulation s = Simulate(sim::SceneKind::kRoom, 40, 3);
  const std::vector<FrameInput> in = WithNoisyPosePriors(s, Inputs(s, 2));
  SlidingWindowOptions options;
  options.window_size = 6;
  options.loss = factors::RobustLoss::kNone;  // the covariance of a Gaussian problem
  const WindowRun run = RunWindow(s, in, options, 3, true);
  ASSERT_TRUE(run.initialized);
  SlidingWindowOptions in_prior = options;  // k0's line observations into the prior at once
  in_prior.retain_line_observer_poses = false;
  const WindowRun prior_lines = RunWindow(s, in, in_prior, 3, true);
  std::printf("line observations into the prior at once: mean NEES %.2f over %d, ATE %.4f m\n",
              prior_lines.mean_nees, prior_lines.nees_count, prior_lines.ate_m);
  options.first_estimate_jacobians = false;
  const WindowRun relinearised = RunWindow(s, in, options, 3, true);
  std::printf(
      "room 40 frames with pose priors: mean NEES of the newest pose %.2f over %d "
      "keyframes (6 expected), ATE %.4f m; without first-estimate Jacobians %.2f\n",
      run.mean_nees, run.nees_count, run.ate_m, relinearised.mean_nees);
  EXPECT_GE(run.nees_count, 8);
  EXPECT_GT(run.mean_nees, 1.0);
  EXPECT_LT(run.mean_nees, 18.0);
  EXPECT_GE(prior_lines.nees_count, 8);
  EXPECT_GT(prior_lines.mean_nees, 1.0);
  EXPECT_LT(prior_lines.mean_nees, 18.0);
}

// The poses-only prior (PriorBlocks::kPoses, the fast mode of `plucker vo` on images): landmarks
// whose track ended are marginalized one by one, the prior lives on the window's poses only
// (rank <= 6 x (window - 1)). Same room as RecoversPosesOnASimulatedRoom, both modes; and the
// NEES run of NeesOfTheNewestPoseIsInASaneBand with the poses-only prior.
TEST(SlidingWindowEstimator, PosesOnlyPriorRecoversPosesAndStaysConsistent) {
  const sim::CameraSimulation s = Simulate(sim::SceneKind::kRoom, 40, 1);
  SlidingWindowOptions landmarks;
  SlidingWindowOptions poses;
  poses.prior_blocks = SlidingWindowOptions::PriorBlocks::kPoses;
  const WindowRun a = RunWindow(s, Inputs(s, 1), landmarks);
  const WindowRun b = RunWindow(s, Inputs(s, 1), poses);
  ASSERT_TRUE(a.initialized && b.initialized);
  std::printf(
      "room 40 frames, all points + lines: ATE landmark prior %.4f m (max rank %d), poses-only "
      "prior %.4f m (max rank %d, %d landmarks marginalized, %d point observations of live "
      "tracks dropped)\n",
      a.ate_m, a.max_prior_rank, b.ate_m, b.max_prior_rank, b.marginalized_landmarks,
      b.point_obs_dropped);
  EXPECT_GT(b.marginalized, 0);
  EXPECT_EQ(b.failed_marginalizations, 0);
  EXPECT_EQ(b.lost, 0);
  EXPECT_GT(b.marginalized_landmarks, 0);
  EXPECT_GT(b.max_prior_rank, 0);
  EXPECT_LE(b.max_prior_rank, 6 * (poses.window_size - 1));
  EXPECT_LT(b.ate_m, 0.05);

  const sim::CameraSimulation n = Simulate(sim::SceneKind::kRoom, 40, 3);
  const std::vector<FrameInput> in = WithNoisyPosePriors(n, Inputs(n, 2));
  poses.window_size = 6;
  poses.loss = factors::RobustLoss::kNone;
  const WindowRun c = RunWindow(n, in, poses, 3, true);
  ASSERT_TRUE(c.initialized);
  std::printf("poses-only prior, room 40 frames with pose priors: mean NEES %.2f over %d (6)\n",
              c.mean_nees, c.nees_count);
  EXPECT_GE(c.nees_count, 8);
  EXPECT_GT(c.mean_nees, 1.0);
  EXPECT_LT(c.mean_nees, 18.0);
}

// PnP fallback: a frame whose prediction is far off (rotated 90 deg, moved 2 m) cannot be tracked
// from it; PnP RANSAC against the window's points recovers its pose. Without the fallback the
// frame is lost.
TEST(SlidingWindowEstimator, PnpFallbackRecoversAFrameWithABadPrediction) {
  const sim::CameraSimulation s = Simulate(sim::SceneKind::kRoom, 20, 1);
  std::vector<FrameInput> in = Inputs(s, 1);
  const int bad = 12;
  Vector6d jump;
  jump << 0.0, M_PI / 2.0, 0.0, 2.0, 0.0, 0.0;
  in[bad].T_w_c_guess = s.T_w_c_gt[bad].Plus(jump);
  for (const bool fallback : {true, false}) {
    SlidingWindowOptions options;
    options.pnp_fallback = fallback;
    SlidingWindowEstimator estimator(s.rig.K, options);
    ASSERT_TRUE(estimator.Initialize(in[0], s.T_w_c_gt[0], in[3], s.T_w_c_gt[3]).ok);
    WindowFrameResult r;
    for (int i = 4; i <= bad; ++i) r = estimator.AddFrame(in[i]);
    const double error = (r.T_w_c.translation() - s.T_w_c_gt[bad].translation()).norm();
    std::printf("bad prediction, PnP fallback %s: ok %d, tried %d, position error %.4f m\n",
                fallback ? "on" : "off", r.ok, r.pnp_fallback, error);
    if (fallback) {
      EXPECT_TRUE(r.pnp_fallback);
      EXPECT_TRUE(r.ok);
      EXPECT_LT(error, 0.05);
      EXPECT_GT(r.tracked_points, 20);
    } else {
      EXPECT_FALSE(r.pnp_fallback);
      EXPECT_FALSE(r.ok && error < 0.05);
    }
  }
}

// Segments that never become lines (an image front end's: MH_05 has 60 a frame and 0-2 lines in
// the window) make every frame a keyframe through min_tracked_ratio unless the ratio counts only
// the segments of mapped lines (tracked_ratio_mapped_segments): then the keyframes are those of
// the run without them. The line statistics of the results add up.
TEST(SlidingWindowEstimator, TrackedRatioOfMappedSegmentsIgnoresSegmentsWithoutLines) {
  const sim::CameraSimulation s = Simulate(sim::SceneKind::kRoom, 20, 1);
  const std::vector<FrameInput> clean = Inputs(s, 1);
  std::vector<FrameInput> cluttered = clean;
  int next_id = 1000000;
  for (FrameInput& f : cluttered) {
    for (int k = 0; k < 200; ++k) {
      sensor::SegmentObservation seg;
      seg.line_id = next_id++;  // a new track in every frame: never triangulated
      seg.s_px = Eigen::Vector2d(20.0 + k, 40.0);
      seg.e_px = Eigen::Vector2d(60.0 + k, 200.0);
      f.segments.push_back(seg);
    }
  }
  const auto keyframes = [&](const std::vector<FrameInput>& in, bool mapped_only) {
    SlidingWindowOptions options;
    options.tracked_ratio_mapped_segments = mapped_only;
    SlidingWindowEstimator estimator(s.rig.K, options);
    EXPECT_TRUE(estimator.Initialize(in[0], s.T_w_c_gt[0], in[3], s.T_w_c_gt[3]).ok);
    std::vector<int> kf;
    int line_residuals = 0;
    for (std::size_t i = 4; i < in.size(); ++i) {
      const WindowFrameResult r = estimator.AddFrame(in[i]);
      if (r.keyframe) kf.push_back(static_cast<int>(i));
      EXPECT_LE(r.culled_line_observations, r.culled_observations);
      EXPECT_LE(r.line_residuals, r.residuals);
      EXPECT_LE(
          r.new_lines + r.line_small_parallax + r.line_ill_conditioned + r.line_other_rejections,
          r.line_candidates);
      EXPECT_TRUE(std::isfinite(r.line_rms_sigmas) && std::isfinite(r.point_rms_sigmas));
      line_residuals += r.line_residuals;
    }
    EXPECT_GT(line_residuals, 0);
    return kf;
  };
  const std::vector<int> clean_kf = keyframes(clean, true);
  const std::vector<int> all_segments = keyframes(cluttered, false);
  std::printf("keyframes: %zu without clutter, %zu with 200 segments a frame counted\n",
              clean_kf.size(), all_segments.size());
  EXPECT_EQ(keyframes(cluttered, true), clean_kf);
  EXPECT_EQ(all_segments.size(), clean.size() - 4);  // every frame
  EXPECT_LT(clean_kf.size(), all_segments.size());
}

// The rotation keyframe and its rate gate: with parallax and tracking never asking for one, the
// room (turning at ~31 deg/s at 10 Hz) gets keyframes every few frames from a 5 deg rotation
// bound at any rate or a rate bound under its turn rate, and none when the bound is above it.
TEST(SlidingWindowEstimator, RotationKeyframesOnlyAtTheirTurnRate) {
  const sim::CameraSimulation s = Simulate(sim::SceneKind::kRoom, 30, 1);
  const std::vector<FrameInput> in = Inputs(s, 1);
  const auto keyframes = [&](double max_rotation_deg, double min_rate_deg_s) {
    SlidingWindowOptions options;
    options.keyframe_parallax_px = 1e9;
    options.min_tracked = 0;
    options.min_tracked_ratio = 0.0;
    options.keyframe_max_rotation_deg = max_rotation_deg;
    options.keyframe_min_turn_rate_deg_s = min_rate_deg_s;
    SlidingWindowEstimator estimator(s.rig.K, options);
    EXPECT_TRUE(estimator.Initialize(in[0], s.T_w_c_gt[0], in[3], s.T_w_c_gt[3]).ok);
    int n = 0;
    for (std::size_t i = 4; i < in.size(); ++i) n += estimator.AddFrame(in[i]).keyframe;
    return n;
  };
  const int off = keyframes(0.0, 0.0), any_rate = keyframes(5.0, 0.0);
  const int slow_bound = keyframes(5.0, 10.0), fast_bound = keyframes(5.0, 200.0);
  std::printf("keyframes: off %d, 5 deg %d, 5 deg at >= 10 deg/s %d, at >= 200 deg/s %d\n", off,
              any_rate, slow_bound, fast_bound);
  EXPECT_EQ(off, 0);
  EXPECT_GE(any_rate, 5);
  EXPECT_EQ(slow_bound, any_rate);
  EXPECT_EQ(fast_bound, 0);
  SlidingWindowOptions bad;
  bad.keyframe_min_turn_rate_deg_s = -1.0;
  EXPECT_THROW(SlidingWindowEstimator(s.rig.K, bad), std::invalid_argument);
}

// The new-line gates: min_line_views keyframes and max_new_line_rms_px (counted among
// line_other_rejections); bad values throw.
TEST(SlidingWindowEstimator, NewLineGatesRejectLines) {
  const sim::CameraSimulation s = Simulate(sim::SceneKind::kRoom, 16, 1);
  const std::vector<FrameInput> in = Inputs(s, 1);
  const auto run = [&](int min_views, double max_rms) {
    SlidingWindowOptions options;
    options.min_line_views = min_views;
    options.max_new_line_rms_px = max_rms;
    SlidingWindowEstimator estimator(s.rig.K, options);
    EXPECT_TRUE(estimator.Initialize(in[0], s.T_w_c_gt[0], in[3], s.T_w_c_gt[3]).ok);
    WindowFrameResult sum;
    for (std::size_t i = 4; i < in.size(); ++i) {
      const WindowFrameResult r = estimator.AddFrame(in[i]);
      sum.new_lines += r.new_lines;
      sum.line_candidates += r.line_candidates;
      sum.line_other_rejections += r.line_other_rejections;
    }
    return sum;
  };
  const WindowFrameResult open = run(2, 0.0), views = run(1000, 0.0), rms = run(2, 1e-9);
  std::printf("new lines: %d of %d tries; 1000 views: %d of %d; RMS 1e-9 px: %d (%d rejected)\n",
              open.new_lines, open.line_candidates, views.new_lines, views.line_candidates,
              rms.new_lines, rms.line_other_rejections);
  EXPECT_GT(open.new_lines, 0);
  EXPECT_EQ(views.new_lines + views.line_candidates, 0);
  EXPECT_EQ(rms.new_lines, 0);
  EXPECT_GT(rms.line_other_rejections, 0);
  SlidingWindowOptions bad;
  bad.min_line_views = 1;
  EXPECT_THROW(SlidingWindowEstimator(s.rig.K, bad), std::invalid_argument);
  bad.min_line_views = 2;
  bad.max_new_line_rms_px = -1.0;
  EXPECT_THROW(SlidingWindowEstimator(s.rig.K, bad), std::invalid_argument);
}

// two_view_line_sigma_scale: after a two-keyframe start every line is a two-view line (its two
// observations fit exactly, so the start's cost is that of its points); a frame localized against
// them with a large scale gets the pose of points alone, and once later keyframes have seen the
// lines three times their whitened residuals are back to those of scale 1.
TEST(SlidingWindowEstimator, TwoViewLinesAreWeighedDownUntilAThirdView) {
  const sim::CameraSimulation s = Simulate(sim::SceneKind::kRoom, 16, 1);
  const std::vector<FrameInput> in = Inputs(s, 1);
  struct Run {
    double start_cost = 0.0, last_line_rms = 0.0;
    SE3d T_w_c2;  // frame 2 localized after the start
  };
  const auto run = [&](bool lines, double scale) {
    SlidingWindowOptions options;
    options.use_lines = lines;
    options.two_view_line_sigma_scale = scale;
    SlidingWindowEstimator estimator(s.rig.K, options);
    const InitializationResult init =
        estimator.Initialize(in[0], s.T_w_c_gt[0], in[3], s.T_w_c_gt[3]);
    EXPECT_TRUE(init.ok);
    Run r{init.final_cost, 0.0, estimator.Localize(in[2], init.T_w_b).value_or(SE3d())};
    for (std::size_t i = 4; i < in.size(); ++i) {
      const WindowFrameResult f = estimator.AddFrame(in[i]);
      if (f.keyframe) r.last_line_rms = f.line_rms_sigmas;
    }
    return r;
  };
  const Run points = run(false, 1.0), full = run(true, 1.0), down = run(true, 1e3);
  const auto moved = [&](const Run& r) {
    return (r.T_w_c2.translation() - points.T_w_c2.translation()).norm();
  };
  std::printf(
      "start cost %.6g / %.6g; frame 2 moved from points only by %.3g m (lines), %.3g m "
      "(x 1000); last line RMS %.3g, %.3g (x 1000)\n",
      points.start_cost, full.start_cost, moved(full), moved(down), full.last_line_rms,
      down.last_line_rms);
  EXPECT_NEAR(full.start_cost, points.start_cost, 1e-6 * points.start_cost);
  EXPECT_GT(moved(full), 1e-4);                // the two-view lines count at scale 1 ...
  EXPECT_LT(moved(down), 0.05 * moved(full));  // ... and hardly at 1000
  EXPECT_GT(full.last_line_rms, 0.3);
  EXPECT_GT(down.last_line_rms, 0.5 * full.last_line_rms);  // seen three times: full weight
  SlidingWindowOptions bad;
  bad.two_view_line_sigma_scale = 0.5;
  EXPECT_THROW(SlidingWindowEstimator(s.rig.K, bad), std::invalid_argument);
}

// two_view_min_plane_angle_px: the start's lines (two views each) need that many pixels' angles
// between their planes; the lines it refuses come in once a third keyframe sees them (5 deg).
TEST(SlidingWindowEstimator, TwoViewLinesNeedThePlaneAngleInPixels) {
  const sim::CameraSimulation s = Simulate(sim::SceneKind::kRoom, 16, 1);
  const std::vector<FrameInput> in = Inputs(s, 1);
  struct Run {
    int start_lines = 0, last_lines = 0;
  };
  const auto run = [&](double px) {
    SlidingWindowOptions options;
    options.two_view_min_plane_angle_px = px;
    SlidingWindowEstimator estimator(s.rig.K, options);
    const InitializationResult init =
        estimator.Initialize(in[0], s.T_w_c_gt[0], in[3], s.T_w_c_gt[3]);
    EXPECT_TRUE(init.ok);
    Run r{init.lines, 0};
    for (std::size_t i = 4; i < in.size(); ++i)
      r.last_lines = estimator.AddFrame(in[i]).window_lines;
    return r;
  };
  // 5 deg at f = 400 is 35.0 px: a smaller bound changes nothing.
  const double f = 0.5 * (s.rig.K.fx + s.rig.K.fy);
  const double five_deg_px = f * std::tan(5.0 * M_PI / 180.0);
  const Run off = run(0.0), below = run(0.99 * five_deg_px), twice = run(2.0 * five_deg_px),
            all = run(1e6);
  std::printf(
      "start lines: off %d, below 5 deg %d, 10 deg %d, all refused %d; last window %d / %d\n",
      off.start_lines, below.start_lines, twice.start_lines, all.start_lines, off.last_lines,
      all.last_lines);
  EXPECT_GE(off.start_lines, 1);
  EXPECT_EQ(below.start_lines, off.start_lines);
  EXPECT_LE(twice.start_lines, off.start_lines);
  EXPECT_EQ(all.start_lines, 0);
  EXPECT_GT(all.last_lines, 10);  // made from three views and more
  SlidingWindowOptions bad;
  bad.two_view_min_plane_angle_px = -1.0;
  EXPECT_THROW(SlidingWindowEstimator(s.rig.K, bad), std::invalid_argument);
}

}  // namespace
}  // namespace window
}  // namespace plucker
