// The visual-inertial mode of the sliding window (SlidingWindowOptions::inertial) on simulated
// rooms: noise-free, with MEMS noise, and the NEES of the newest pose.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <deque>

#include "plucker/eval/ate.h"
#include "plucker/sim/camera_observations.h"
#include "plucker/window/sliding_window_estimator.h"

namespace plucker {
namespace window {
namespace {

struct VioRun {
  std::vector<SE3d> gt, est;  // T_w_b per frame
  int keyframes = 0, marginalized = 0, imu_only = 0, failed_marginalizations = 0;
  double max_error_m = 0.0;
  double mean_imu_chi2 = 0.0;
  double mean_nees = 0.0;
  int nees_count = 0;
  bool initialized = false;
};

sim::CameraSimulation Simulate(int frames, bool noise, std::uint64_t seed) {
  sim::CameraSimulationOptions o;
  o.scene.kind = sim::SceneKind::kRoom;
  o.num_frames = frames;
  o.seed = seed;
  if (!noise) {
    o.obs.pixel_sigma = 0.0;
    o.imu.model.gyro_noise_density = 0.0;
    o.imu.model.accel_noise_density = 0.0;
    o.imu.model.gyro_bias_random_walk = 0.0;
    o.imu.model.accel_bias_random_walk = 0.0;
  }
  return sim::SimulateCamera(o);
}

InertialState TrueState(const sim::CameraSimulation& s, int i) {
  InertialState st;
  st.T_w_b = s.T_w_b_gt[i];
  st.v_w = s.v_w_gt[i];
  // The sample nearest the frame carries the true biases.
  std::size_t k = 0;
  while (k + 1 < s.imu.size() && s.imu[k + 1].t <= s.frame_times[i]) ++k;
  st.bias.gyro = s.imu[k].gyro_bias;
  st.bias.accel = s.imu[k].accel_bias;
  return st;
}

// Initialised from the true states of frames 0 and `second` (a test may), frames in between at
// the truth, the rest through AddFrame.
VioRun RunVio(const sim::CameraSimulation& s, SlidingWindowOptions options, bool nees,
              int point_stride = 1, int second = 3) {
  options.inertial = InertialOptions();
  options.inertial->T_b_c = s.rig.T_b_c;
  options.inertial->gravity_w = s.imu_options.gravity_w;
  VioRun run;
  std::vector<FrameInput> in(s.frame_times.size());
  for (std::size_t i = 0; i < in.size(); ++i) in[i].time = s.frame_times[i];
  for (const auto& p : s.points)
    if (p.point_id % point_stride == 0) in[p.frame].points.push_back(p);
  for (const auto& l : s.segments) in[l.frame].segments.push_back(l);
  SlidingWindowEstimator estimator(s.rig.K, options);
  estimator.AddImu(s.imu);
  const InitializationResult init =
      estimator.InitializeInertial(in[0], TrueState(s, 0), in[second], TrueState(s, second), 10);
  run.initialized = init.ok;
  if (!init.ok) return run;
  for (int i = 0; i <= second; ++i) run.est.push_back(s.T_w_b_gt[i]);
  double chi2 = 0.0, nees_sum = 0.0;
  std::deque<int> keyframe_frames = {0, second};
  for (std::size_t i = second + 1; i < in.size(); ++i) {
    const FrameResult r = estimator.AddFrame(in[i]);
    run.est.push_back(r.state.T_w_b);
    run.keyframes += r.keyframe;
    run.marginalized += r.marginalized_keyframes;
    run.failed_marginalizations += r.marginalization_failed;
    run.imu_only += r.imu_only;
    chi2 += r.imu_chi2;
    if (r.keyframe) keyframe_frames.push_back(static_cast<int>(i));
    if (r.marginalized_keyframes) keyframe_frames.pop_front();
    if (nees && r.keyframe) {
      // Relative to the oldest keyframe (held: the gauge): the estimate moved so that its oldest
      // keyframe is the true one, the error in the PoseManifold tangent of the newest pose.
      const auto cov = estimator.NewestPoseCovariance();
      if (cov) {
        const SE3d& old_gt = s.T_w_b_gt[keyframe_frames.front()];
        const SE3d align = old_gt * estimator.KeyframeStates().front().T_w_b.Inverse();
        const Vector6d e = (align * r.state.T_w_b).Minus(s.T_w_b_gt[i]);
        nees_sum += e.dot(cov->ldlt().solve(e));
        ++run.nees_count;
      }
    }
  }
  run.mean_imu_chi2 = run.keyframes ? chi2 / run.keyframes : 0.0;
  for (std::size_t i = 0; i < run.est.size(); ++i) {
    run.gt.push_back(s.T_w_b_gt[i]);
    run.max_error_m =
        std::max(run.max_error_m, (run.est[i].translation() - s.T_w_b_gt[i].translation()).norm());
  }
  if (run.nees_count) run.mean_nees = nees_sum / run.nees_count;
  return run;
}

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
  EXPECT_LT(run.mean_nees, 30.0);
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
    const FrameResult r = estimator.AddFrame(in[i]);
    finite += r.state.T_w_b.translation().allFinite() && r.state.v_w.allFinite();
    EXPECT_LT((r.state.T_w_b.translation() - s.T_w_b_gt[i].translation()).norm(), 0.2) << i;
  }
  EXPECT_EQ(finite, static_cast<int>(in.size()) - 11);
  EXPECT_THROW(SlidingWindowEstimator(s.rig.K, SlidingWindowOptions()).AddImu(late),
               std::logic_error);
}

}  // namespace
}  // namespace window
}  // namespace plucker
