// The visual-inertial mode of the sliding window (SlidingWindowOptions::inertial) on simulated
// rooms: noise-free, with MEMS noise, and the NEES of the newest pose.
#include <ceres/autodiff_cost_function.h>
#include <ceres/loss_function.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>

#include "plucker/eval/ate.h"
#include "plucker/factors/held_extrinsic_factor.h"
#include "plucker/factors/imu_factor.h"
#include "plucker/factors/marginalization.h"
#include "plucker/factors/point_reprojection_factor.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/sim/camera_observations.h"
#include "plucker/window/sliding_window_estimator.h"
#include "plucker/window/visual_inertial_test_utils.h"
#include "plucker/window/window_test_utils.h"

namespace plucker {
namespace window {
namespace {

TEST(VisualInertialWindow, NoiseFreeRecoversThePosesToAMillimetre) {
  const sim::CameraSimulation s = Simulate(60, false, 3);
  SlidingWindowOptions options;
  const VioRun run = RunVio(s, options, false, 2);
  ASSERT_TRUE(run.initialized);
  std::printf(
      "noise-free VIO room: %zu frames, %d keyframes (%d marginalized), max error %.2e m, "
      "mean IMU chi2 %.2e\n",
      run.est.size(), run.keyframes, run.marginalized, run.max_error_m, run.mean_imu_chi2);
  EXPECT_EQ(run.est.size(), s.frame_times.size());
  EXPECT_GT(run.marginalized, 10);
  EXPECT_EQ(run.failed_marginalizations, 0);
  EXPECT_LT(run.max_error_m, 1e-3);
}

// MEMS-like IMU noise (the simulator's default model, also the estimator's) and 1 px pixel noise:
// the position + yaw aligned ATE over 20 s, and the NEES of the newest pose (6 expected).
TEST(VisualInertialWindow, MemsNoiseGivesASmallPositionYawAteAndASaneNees) {
  const sim::CameraSimulation s = Simulate(200, true, 5);
  SlidingWindowOptions options;
  const VioRun run = RunVio(s, options, true, 3);
  ASSERT_TRUE(run.initialized);
  const eval::AteResult ate =
      eval::ComputeAte(run.gt, run.est, {eval::AlignmentMode::kPositionYaw});
  std::printf(
      "MEMS VIO room: %zu frames, %d keyframes, ATE (posyaw) %.4f m, max error %.4f m, "
      "mean IMU chi2 %.3g (15 dof), mean NEES %.2f over %d keyframes (6 expected), "
      "%d IMU-only frames\n",
      run.est.size(), run.keyframes, ate.translation_m.rmse, run.max_error_m, run.mean_imu_chi2,
      run.mean_nees, run.nees_count, run.imu_only);
  EXPECT_EQ(run.failed_marginalizations, 0);
  EXPECT_LT(ate.translation_m.rmse, 0.05);
  EXPECT_GT(run.nees_count, 20);
  EXPECT_LT(run.mean_nees, 12.0);  // 6.42 (13.0 when the covariance held roll and pitch)
  EXPECT_GT(run.mean_nees, 3.0);
}

// The per-frame tracking with the IMU prediction as a prior (InertialOptions::
// tracking_velocity_sigma) against vision-only tracking (0), MEMS room, 4 s: the frames between
// keyframes, whose pose is the tracking's, relative to the keyframe they were predicted from
// (the error of a frame minus the error of that keyframe) are several times closer to the truth.
TEST(VisualInertialWindow, TrackingWithTheImuPredictionIsCloserThanVisionOnly) {
  const sim::CameraSimulation s = Simulate(40, true, 5);
  double local_rms[2] = {0.0, 0.0};
  int frames[2] = {0, 0};
  for (int with_imu = 0; with_imu < 2; ++with_imu) {
    SlidingWindowOptions options;
    options.inertial = InertialOptions();
    if (!with_imu) options.inertial->tracking_velocity_sigma = 0.0;
    const VioRun run = RunVio(s, options, false, 3);
    ASSERT_TRUE(run.initialized);
    ASSERT_EQ(run.est.size(), s.frame_times.size());
    double sum = 0.0;
    for (std::size_t i = 1; i < run.est.size(); ++i) {
      if (run.keyframe_of[i] < 0 || run.keyframe_of[i] == static_cast<int>(i)) continue;
      const int k = run.keyframe_of[i];
      const Eigen::Vector3d e = run.est[i].translation() - run.gt[i].translation();
      const Eigen::Vector3d e_k = run.est[k].translation() - run.gt[k].translation();
      sum += (e - e_k).squaredNorm();
      ++frames[with_imu];
    }
    local_rms[with_imu] = std::sqrt(sum / std::max(frames[with_imu], 1));
    const eval::AteResult ate =
        eval::ComputeAte(run.gt, run.est, {eval::AlignmentMode::kPositionYaw});
    std::printf(
        "%s tracking: %d frames between keyframes, error relative to their keyframe "
        "%.2f mm rms, ATE (posyaw) %.4f m\n",
        with_imu ? "IMU-prior" : "vision-only", frames[with_imu], 1e3 * local_rms[with_imu],
        ate.translation_m.rmse);
  }
  EXPECT_GE(frames[0], 10);
  EXPECT_GE(frames[1], 10);
  EXPECT_LT(local_rms[1], 0.5 * local_rms[0]);
  // A negative or non-finite velocity sigma is refused.
  SlidingWindowOptions bad;
  bad.inertial = InertialOptions();
  bad.inertial->tracking_velocity_sigma = -0.01;
  EXPECT_THROW(SlidingWindowEstimator(s.rig.K, bad), std::invalid_argument);
  bad.inertial->tracking_velocity_sigma = std::numeric_limits<double>::infinity();
  EXPECT_THROW(SlidingWindowEstimator(s.rig.K, bad), std::invalid_argument);
}

// Bad IMU input: samples that go back are refused; a frame the samples do not cover yet is
// refused (std::invalid_argument) without changing the window, which goes on once they arrive.
TEST(VisualInertialWindow, UncoveredFramesAreRefusedAndTheWindowGoesOn) {
  const sim::CameraSimulation s = Simulate(30, true, 2);
  SlidingWindowOptions options;
  options.inertial = InertialOptions();
  options.inertial->T_b_c = s.rig.T_b_c;
  std::vector<FrameInput> in(s.frame_times.size());
  for (std::size_t i = 0; i < in.size(); ++i) in[i].time = s.frame_times[i];
  for (const auto& p : s.points) in[p.frame].points.push_back(p);
  SlidingWindowEstimator estimator(s.rig.K, options);
  const double t_cut = s.frame_times[10] + 0.01;
  std::vector<sensor::ImuSample> early, late;
  for (const auto& m : s.imu) (m.t <= t_cut ? early : late).push_back(m);
  estimator.AddImu(early);
  EXPECT_THROW(estimator.AddImu({early.front()}), std::invalid_argument);
  ASSERT_TRUE(estimator.InitializeInertial(in[0], TrueState(s, 0), in[3], TrueState(s, 3)).ok);
  for (int i = 4; i <= 10; ++i) ASSERT_NO_THROW(estimator.AddFrame(in[i]));
  const std::size_t keyframes = estimator.KeyframeStates().size();
  EXPECT_THROW(estimator.AddFrame(in[11]), std::invalid_argument);
  EXPECT_EQ(estimator.KeyframeStates().size(), keyframes);
  estimator.AddImu(late);
  int finite = 0;
  for (std::size_t i = 11; i < in.size(); ++i) {
    const WindowFrameResult r = estimator.AddFrame(in[i]);
    finite += r.state.T_w_b.translation().allFinite() && r.state.v_w.allFinite();
    EXPECT_LT((r.state.T_w_b.translation() - s.T_w_b_gt[i].translation()).norm(), 0.2) << i;
  }
  EXPECT_EQ(finite, static_cast<int>(in.size()) - 11);
  EXPECT_THROW(SlidingWindowEstimator(s.rig.K, SlidingWindowOptions()).AddImu(late),
               std::logic_error);
}

TEST(VisualInertialWindow, StartsWithManyKeyframesAndTriangulatesTheLandmarksOfEach) {
  const sim::CameraSimulation s = Simulate(30, false, 3);
  SlidingWindowOptions options;
  options.inertial = InertialOptions();
  options.inertial->T_b_c = s.rig.T_b_c;
  options.inertial->gravity_w = s.imu_options.gravity_w;
  std::vector<FrameInput> in(s.frame_times.size());
  for (std::size_t i = 0; i < in.size(); ++i) in[i].time = s.frame_times[i];
  for (const auto& p : s.points) in[p.frame].points.push_back(p);
  const std::vector<int> kf = {0, 5, 10, 15, 20};
  std::vector<FrameInput> frames;
  std::vector<sensor::BodyState> states;
  for (int f : kf) {
    frames.push_back(in[f]);
    states.push_back(TrueState(s, f));
  }
  // Perturbed starts (as an alignment gives them): the window's solve brings them back.
  for (std::size_t k = 1; k < states.size(); ++k) {
    states[k].T_w_b = SE3d(states[k].T_w_b.rotation(),
                           states[k].T_w_b.translation() + Eigen::Vector3d(0.03, -0.02, 0.01));
  }
  SlidingWindowEstimator many(s.rig.K, options), two(s.rig.K, options);
  many.AddImu(s.imu);
  two.AddImu(s.imu);
  const InitializationResult r = many.InitializeInertial(frames, states, 10);
  ASSERT_TRUE(r.ok);
  ASSERT_TRUE(two.InitializeInertial(in[0], TrueState(s, 0), in[20], TrueState(s, 20), 10).ok);
  const std::vector<sensor::BodyState> solved = many.KeyframeStates();
  ASSERT_EQ(solved.size(), kf.size());
  double max_error = 0.0;
  for (std::size_t k = 0; k < kf.size(); ++k) {
    max_error = std::max(max_error,
                         (solved[k].T_w_b.translation() - s.T_w_b_gt[kf[k]].translation()).norm());
  }
  std::printf("5-keyframe start: %d points (2 keyframes: %zu), max position error %.2e m\n",
              r.points, two.Points().size(), max_error);
  EXPECT_LT(max_error, 2e-3);  // noise-free: the 3.7 cm perturbations are removed
  EXPECT_GT(r.points, static_cast<int>(two.Points().size()));  // tracks not seen by the newest
  for (int i = 21; i < 30; ++i) {
    const WindowFrameResult fr = many.AddFrame(in[i]);
    EXPECT_LT((fr.state.T_w_b.translation() - s.T_w_b_gt[i].translation()).norm(), 5e-3) << i;
  }
  EXPECT_THROW(many.InitializeInertial(frames, {states.front()}), std::invalid_argument);
  options.window_size = 4;
  SlidingWindowEstimator small(s.rig.K, options);
  small.AddImu(s.imu);
  EXPECT_THROW(small.InitializeInertial(frames, states), std::invalid_argument);
}

// The caller's "no image motion" flag: believed for a standing body (its pose held by the
// zero-motion factors against an accelerometer offset), ignored for a moving one (forward motion
// can look still in the image).
TEST(VisualInertialWindow, TheStationaryFlagHoldsAStandingBodyAndIsIgnoredWhenItMoves) {
  const sim::CameraSimulation s = Simulate(16, true, 5);  // short: sanitizer budget
  SlidingWindowOptions options;
  options.inertial = InertialOptions();
  options.inertial->T_b_c = s.rig.T_b_c;
  options.inertial->gravity_w = s.imu_options.gravity_w;
  {  // Standing: frame 0's view repeated, the IMU reading gravity plus a 0.05 m/s^2 offset.
    sensor::BodyState still;
    still.T_w_b = s.T_w_b_gt[0];
    std::vector<sensor::ImuSample> imu;
    for (int k = 0; k <= 500; ++k) {
      sensor::ImuSample m;
      m.t = 0.005 * k;
      m.accel = still.T_w_b.RotationMatrix().transpose() * -s.imu_options.gravity_w +
                Eigen::Vector3d(0.05, 0.0, 0.0);
      imu.push_back(m);
    }
    std::vector<FrameInput> in(21);
    for (std::size_t i = 0; i < in.size(); ++i) {
      in[i].time = 0.1 * static_cast<double>(i);
      in[i].stationary = true;
      for (const auto& p : s.points)
        if (p.frame == 0) in[i].points.push_back(p);
    }
    SlidingWindowEstimator estimator(s.rig.K, options);
    estimator.AddImu(imu);
    ASSERT_TRUE(estimator.InitializeInertial(in[0], still, in[1], still, 0).ok);
    int held = 0;
    double drift = 0.0;
    for (std::size_t i = 2; i < in.size(); ++i) {
      const WindowFrameResult r = estimator.AddFrame(in[i]);
      held += r.stationary;
      drift = std::max(drift, (r.state.T_w_b.translation() - still.T_w_b.translation()).norm());
    }
    std::printf("standing body: %d of %zu frames held, drift %.2e m (the offset alone: %.3f m)\n",
                held, in.size() - 2, drift, 0.5 * 0.05 * 2.0 * 2.0);
    EXPECT_EQ(held, static_cast<int>(in.size()) - 2);
    EXPECT_LT(drift, 2e-3);
  }
  {  // Moving, every frame flagged: the flags are ignored, the poses tracked.
    std::vector<FrameInput> in(s.frame_times.size());
    for (std::size_t i = 0; i < in.size(); ++i) {
      in[i].time = s.frame_times[i];
      in[i].stationary = true;
    }
    for (const auto& p : s.points) in[p.frame].points.push_back(p);
    SlidingWindowEstimator estimator(s.rig.K, options);
    estimator.AddImu(s.imu);
    ASSERT_GT(s.v_w_gt[3].norm(), 5.0 * options.inertial->stationary_max_speed);
    ASSERT_TRUE(estimator.InitializeInertial(in[0], TrueState(s, 0), in[3], TrueState(s, 3)).ok);
    int held = 0, checked = 0;
    for (std::size_t i = 4; i < in.size(); ++i) {
      const WindowFrameResult r = estimator.AddFrame(in[i]);
      held += r.stationary;
      EXPECT_LT((r.state.T_w_b.translation() - s.T_w_b_gt[i].translation()).norm(), 0.1) << i;
      ++checked;
    }
    EXPECT_EQ(held, 0);
    EXPECT_EQ(checked, static_cast<int>(in.size()) - 4);
  }
}

}  // namespace
}  // namespace window
}  // namespace plucker
