// Online camera-IMU time offset estimation of the visual-inertial window
// (InertialOptions::estimate_time_offset) on a simulated MEMS room whose IMU stamps run late.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <utility>

#include "plucker/eval/ate.h"
#include "plucker/sim/camera_observations.h"
#include "plucker/window/sliding_window_estimator.h"
#include "plucker/window/window_test_utils.h"

namespace plucker {
namespace window {
namespace {

constexpr int kFrames = 100;  // 10 s at 10 Hz
constexpr int kFirst = 2;     // the start: the shifted IMU must cover the first frame

sim::CameraSimulation MemsRoom(int frames = kFrames, bool noise = true) {
  sim::CameraSimulationOptions o;
  o.scene.kind = sim::SceneKind::kRoom;
  o.num_frames = frames;
  o.seed = 5;
  if (!noise) {
    o.obs.pixel_sigma = 0.0;
    o.imu.model.gyro_noise_density = o.imu.model.accel_noise_density = 0.0;
    o.imu.model.gyro_bias_random_walk = o.imu.model.accel_bias_random_walk = 0.0;
  }
  return sim::SimulateCamera(o);
}

struct OffsetRun {
  double ate_m = 0.0;  // position + yaw aligned, body poses
  double td = 0.0;     // TimeOffsetEstimate() at the end
  int frames = 0;
  std::vector<SE3d> est;
};

// Exact image velocities of the point observations: central differences of the noise-free
// observations of the frames before and after (the same scene and trajectory without noise).
void GiveExactPointVelocities(const sim::CameraSimulation& clean, std::vector<FrameInput>* in) {
  std::map<std::pair<int, int>, Eigen::Vector2d> uv;
  for (const auto& p : clean.points) uv.emplace(std::make_pair(p.frame, p.point_id), p.uv);
  for (std::size_t i = 1; i + 1 < in->size(); ++i) {
    const double dt = (*in)[i + 1].time - (*in)[i - 1].time;
    for (auto& p : (*in)[i].points) {
      const auto a = uv.find({static_cast<int>(i) - 1, p.point_id});
      const auto b = uv.find({static_cast<int>(i) + 1, p.point_id});
      if (a != uv.end() && b != uv.end()) p.uv_velocity = (b->second - a->second) / dt;
    }
  }
}

struct RunOptions {
  bool give_velocity = false;  // every point observation carries a (wrong) image velocity
  bool use_lines = true;
  const sim::CameraSimulation* exact_velocities_from = nullptr;  // GiveExactPointVelocities
  bool velocity_from_state = true;  // InertialOptions::time_offset_velocity_from_state
};

// The window (every third point track: the sanitizer budget, poses-only prior as `plucker vio`)
// started at the true states of frames kFirst and kFirst + 3, with the IMU stamps moved by
// `imu_shift` s (late: positive, t_imu = t_cam + shift). `give_velocity` velocities are nonsense
// that only the time offset estimation may use.
OffsetRun RunWindow(const sim::CameraSimulation& s, double imu_shift, bool estimate,
                    const RunOptions& run_options = {}) {
  SlidingWindowOptions options;
  options.prior_blocks = SlidingWindowOptions::PriorBlocks::kPoses;
  options.retire_marginalized_tracks = false;
  options.inertial = InertialOptions();
  options.inertial->T_b_c = s.rig.T_b_c;
  options.inertial->gravity_w = s.imu_options.gravity_w;
  options.inertial->estimate_time_offset = estimate;
  options.inertial->time_offset_velocity_from_state = run_options.velocity_from_state;
  options.use_lines = run_options.use_lines;
  std::vector<FrameInput> in(s.frame_times.size());
  for (std::size_t i = 0; i < in.size(); ++i) in[i].time = s.frame_times[i];
  for (const auto& p : s.points)
    if (p.point_id % 3 == 0) in[p.frame].points.push_back(p);
  for (const auto& l : s.segments) in[l.frame].segments.push_back(l);
  if (run_options.exact_velocities_from)
    GiveExactPointVelocities(*run_options.exact_velocities_from, &in);
  if (run_options.give_velocity) {
    for (auto& f : in)
      for (auto& p : f.points) p.uv_velocity = Eigen::Vector2d(1e3, -1e3);  // nonsense: unused
  }
  std::vector<sensor::ImuSample> imu = s.imu;
  for (auto& m : imu) m.t += imu_shift;
  SlidingWindowEstimator estimator(s.rig.K, options);
  estimator.AddImu(imu);
  OffsetRun run;
  const int second = kFirst + 3;
  if (!estimator
           .InitializeInertial(in[kFirst], TrueState(s, kFirst), in[second], TrueState(s, second),
                               10)
           .ok)
    return run;
  std::vector<SE3d> gt;
  for (int i = kFirst; i <= second; ++i) {
    gt.push_back(s.T_w_b_gt[i]);
    run.est.push_back(s.T_w_b_gt[i]);
  }
  for (std::size_t i = second + 1; i < in.size(); ++i) {
    const WindowFrameResult r = estimator.AddFrame(in[i]);
    gt.push_back(s.T_w_b_gt[i]);
    run.est.push_back(r.state.T_w_b);
  }
  run.frames = static_cast<int>(run.est.size());
  run.ate_m = eval::ComputeAte(gt, run.est, {eval::AlignmentMode::kPositionYaw}).translation_m.rmse;
  run.td = estimator.TimeOffsetEstimate();
  return run;
}

// The room with the IMU `imu_shift` late, td held at 0 and estimated (printed, both full length).
std::pair<OffsetRun, OffsetRun> HeldAndEstimated(double imu_shift, const RunOptions& o = {}) {
  const sim::CameraSimulation s = MemsRoom();
  const OffsetRun held = RunWindow(s, imu_shift, false, o);
  const OffsetRun estimated = RunWindow(s, imu_shift, true, o);
  for (const OffsetRun* r : {&held, &estimated}) {
    std::printf("room, IMU %+.0f ms, td %-9s ATE %.4f m, td %+.5f s, %d frames\n", 1e3 * imu_shift,
                r == &held ? "held:" : "estimated:", r->ate_m, r->td, r->frames);
    EXPECT_EQ(r->frames, kFrames - kFirst);
  }
  return {held, estimated};
}

// The differenced image velocities (time_offset_velocity_from_state = false), IMU stamps 8 ms
// late: the estimate takes the sign of the shift (Kalibr's convention, t_imu = t_cam + td) and at
// least 2/3 of it, and the ATE is below the held run's; measured +5.62 ms, ATE 0.0176 m against
// 0.0263 m held (with the lagged velocities before the central differences: +4.98 ms, ATE
// 0.0374 m, worse than held). Without a shift within 0.5 ms of 0: measured +0.28 ms (lagged:
// +1.11 ms, the errors-in-variables bias of window_time_offset.cc). Their noise dilutes the
// estimate (docs/math/time-offset.md). (An early IMU would leave this harness's first frames
// uncovered.)
TEST(TimeOffsetEstimation, DifferencedVelocitiesRecoverMostOfTheShift) {
  RunOptions differenced;
  differenced.velocity_from_state = false;
  const auto [held, estimated] = HeldAndEstimated(0.008, differenced);
  EXPECT_EQ(held.td, 0.0);
  EXPECT_GT(estimated.td, 0.008 * 2.0 / 3.0);
  EXPECT_LT(estimated.td, 0.008);
  EXPECT_LT(estimated.ate_m, held.ate_m);
  const auto [held0, estimated0] = HeldAndEstimated(0.0, differenced);
  EXPECT_NEAR(estimated0.td, 0.0, 0.5e-3);
}

// The model is unbiased given exact velocities: noise-free, points only, the velocities of the
// noise-free observations: +8.48 ms for +8 ms (+7.58 ms before the observations left without a
// velocity here, first and last of a track, took the predicted one instead of a differenced one;
// with lines, whose velocities were then zero, 6.27 ms). What is missing with the window's own
// velocities is their noise (regression dilution: 1 px over two frame intervals) and the lines
// (docs/math/time-offset.md).
TEST(TimeOffsetEstimation, ExactVelocitiesRecoverTheShift) {
  const sim::CameraSimulation clean = MemsRoom(kFrames, false);
  RunOptions o;
  o.use_lines = false;
  o.exact_velocities_from = &clean;
  const OffsetRun run = RunWindow(clean, 0.008, true, o);
  std::printf("noise-free room, points only, exact velocities: td %+.5f s\n", run.td);
  ASSERT_EQ(run.frames, kFrames - kFirst);
  EXPECT_NEAR(run.td, 0.008, 0.8e-3);
}

// The targets (26, section 3) with the image velocities predicted from the state (the
// default): within 1 ms of the shift, within 1 ms of 0 without one, the ATE within 10 % of the
// held run. Measured +8.61 ms for +8 ms (ATE 0.0181 m, held 0.0263 m) and +0.92 ms without a
// shift (ATE 0.0164 m, held 0.0246 m). On the real MH_05 clip: docs/results/vio.md.
TEST(TimeOffsetEstimation, WithinOneMillisecondOfTheShift) {
  const auto [held, estimated] = HeldAndEstimated(0.008);
  EXPECT_NEAR(estimated.td, 0.008, 1e-3);
  EXPECT_LT(estimated.ate_m, held.ate_m);
  const auto [held0, estimated0] = HeldAndEstimated(0.0);
  EXPECT_NEAR(estimated0.td, 0.0, 1e-3);
  EXPECT_LT(estimated0.ate_m, 1.1 * held0.ate_m);
}

// Off: the velocities of the observations are not looked at and td stays the given value (the
// results equal, to the bit, those without velocities; the byte-identity with the code before
// the option is checked on `plucker vio` outputs, docs/results).
TEST(TimeOffsetEstimation, OffIgnoresTheVelocities) {
  const sim::CameraSimulation s = MemsRoom(40, false);
  const OffsetRun plain = RunWindow(s, 0.0, false);
  RunOptions o;
  o.give_velocity = true;
  const OffsetRun with_velocity = RunWindow(s, 0.0, false, o);
  ASSERT_EQ(plain.frames, 40 - kFirst);
  ASSERT_EQ(with_velocity.est.size(), plain.est.size());
  for (std::size_t i = 0; i < plain.est.size(); ++i) {
    EXPECT_EQ(plain.est[i].translation(), with_velocity.est[i].translation()) << i;
    EXPECT_EQ(plain.est[i].rotation().coeffs(), with_velocity.est[i].rotation().coeffs()) << i;
  }
  EXPECT_EQ(plain.td, 0.0);
}

}  // namespace
}  // namespace window
}  // namespace plucker
