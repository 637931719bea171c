// The restart after scans missing at speed (LidarOdometryOptions::restart_from_stamps): the
// prediction scales with the elapsed scan time and the scan takes the start path.
#include <gtest/gtest.h>

#include <cstdio>

#include <cmath>
#include <vector>

#include "plucker/lidar/odometry.h"
#include "plucker/sensor/lidar_model.h"
#include "plucker/sim/lidar_scene.h"
#include "plucker/sim/lidar_sim.h"

namespace plucker {
namespace lidar {
namespace {

TEST(LidarOdometryRestartTest, PredictionScalesWithTheElapsedTime) {
  const SE3d T_step(ExpSO3<double>(Eigen::Vector3d(0, 0, 0.02)), Eigen::Vector3d(2, 0, 0));
  const std::vector<SE3d> T_w_s{SE3d(), T_step};
  int steps = 0;
  // One period: exactly PredictPose (the default figures stay bit-identical).
  const SE3d one = PredictPoseAt(T_w_s, {0.0, 0.1}, 0.2, true, &steps);
  EXPECT_EQ(steps, 1);
  EXPECT_EQ((one.translation() - PredictPose(T_w_s, true).translation()).norm(), 0.0);
  // Three scans never given: the step four times, from the times alone.
  const SE3d four = PredictPoseAt(T_w_s, {0.0, 0.1}, 0.5, true, &steps);
  EXPECT_EQ(steps, 4);
  SE3d expected = T_step;
  for (int k = 0; k < 4; ++k) expected = expected * T_step;
  EXPECT_LT((four.translation() - expected.translation()).norm(), 1e-12);
  // The scan after the gap: the last motion spans four periods, one of them is predicted.
  const std::vector<SE3d> after{T_step, expected};
  const SE3d next = PredictPoseAt(after, {0.1, 0.5}, 0.6, true, &steps);
  EXPECT_EQ(steps, 1);
  EXPECT_LT((next.translation() - (expected * T_step).translation()).norm(), 0.01);
  EXPECT_LT(LogSO3(next.rotation().conjugate() * (expected * T_step).rotation()).norm(), 1e-9);
  // No times: PredictPose.
  PredictPoseAt(T_w_s, {0.0, 0.0}, 0.0, true, &steps);
  EXPECT_EQ(steps, 1);
}

// 20 m/s (2 m per scan) through the simulated streets; scans 4-6 never reach the odometry (as
// deleted files in an unnumbered folder): only the scan times show the 8 m gap. Returns the
// translation errors (m) of the pairs 3-7 (across the gap) and 7-8.
std::vector<double> PairErrorsAcrossAGap(const LidarOdometryOptions& options) {
  const sim::LidarScene scene = sim::MakeUrbanScene();
  sim::VehicleTrajectoryOptions motion;
  motion.speed = 20.0;
  const sim::VehicleTrajectory trajectory(scene.route, motion);
  const sim::LidarSimulator simulator(
      scene, sim::LidarSimOptionsFor(sensor::LidarModelFromName("vlp32"), 0.01, false));
  LidarOdometry odometry(options);
  const std::vector<int> given{0, 1, 2, 3, 7, 8};
  std::vector<SE3d> T_gt;
  for (int i : given) {
    const double t = 5.0 + 0.1 * i;
    T_gt.push_back(trajectory.T_w_s(t));
    odometry.ProcessScan(simulator.Scan(trajectory, t, i));
  }
  const std::vector<SE3d>& T = odometry.poses();
  std::vector<double> errors;
  for (std::size_t j = 3; j + 1 < given.size(); ++j) {
    const SE3d E = (T_gt[j].Inverse() * T_gt[j + 1]).Inverse() * (T[j].Inverse() * T[j + 1]);
    errors.push_back(E.translation().norm());
  }
  return errors;
}

TEST(LidarOdometryRestartTest, ScansMissingAtSpeedRestartFromTheScanTimes) {
  const std::vector<double> now = PairErrorsAcrossAGap(LidarOdometryOptions());
  EXPECT_LT(now[0], 0.05) << "across the gap";
  EXPECT_LT(now[1], 0.05) << "the pair after it";
  // The same without the restart handling: the scene does test it (the prediction is 6 m short).
  LidarOdometryOptions before;
  before.restart_from_stamps = false;
  before.restart_min_plane_match = 0.0;
  EXPECT_GT(PairErrorsAcrossAGap(before)[0], 1.0);
}

// 20 m/s again; scans 1 to `skipped` are unreadable (SkipFrame with their times): no velocity is
// known yet, the scan after the gap is 2 (skipped + 1) m from the first (6 m for 2). Returns the
// errors of the pairs across the gap (0 to skipped + 1) and the one after it.
std::vector<double> PairErrorsAfterAGapAtTheStart(const LidarOdometryOptions& options,
                                                  int skipped = 2) {
  const sim::LidarScene scene = sim::MakeUrbanScene();
  sim::VehicleTrajectoryOptions motion;
  motion.speed = 20.0;
  const sim::VehicleTrajectory trajectory(scene.route, motion);
  const sim::LidarSimulator simulator(
      scene, sim::LidarSimOptionsFor(sensor::LidarModelFromName("vlp32"), 0.01, false));
  LidarOdometry odometry(options);
  std::vector<SE3d> T_gt;
  for (int i = 0; i < skipped + 3; ++i) {
    const double t = 5.0 + 0.1 * i;
    T_gt.push_back(trajectory.T_w_s(t));
    if (i >= 1 && i <= skipped) {
      odometry.SkipFrame("unreadable", t);
    } else {
      odometry.ProcessScan(simulator.Scan(trajectory, t, i));
    }
  }
  const std::vector<SE3d>& T = odometry.poses();
  std::vector<double> errors;
  for (const auto& [a, b] : {std::pair{0, skipped + 1}, std::pair{skipped + 1, skipped + 2}}) {
    const SE3d E = (T_gt[a].Inverse() * T_gt[b]).Inverse() * (T[a].Inverse() * T[b]);
    errors.push_back(E.translation().norm());
  }
  return errors;
}

TEST(LidarOdometryRestartTest, GapRightAfterTheFirstScanConvergesWithTheWideStart) {
  const std::vector<double> now = PairErrorsAfterAGapAtTheStart(LidarOdometryOptions());
  EXPECT_LT(now[0], 0.05) << "across the gap (6 m)";
  EXPECT_LT(now[1], 0.05) << "the pair after it";
  // Without the wide start the start path from the first pose stops short (the scene tests it).
  LidarOdometryOptions before;
  before.start_max_speed = 0.0;
  EXPECT_GT(PairErrorsAfterAGapAtTheStart(before)[0], 1.0);
}

// A 12 m gap (5 scans): the right offset matches fewer points than offset 0 against the one-scan
// map, and only its information along the road tells it apart (odometry_start.cc); the pair
// after it needs the gap's motion spread over its periods (else a 12 m step is predicted).
TEST(LidarOdometryRestartTest, TwelveMetreGapRightAfterTheFirstScan) {
  const std::vector<double> now = PairErrorsAfterAGapAtTheStart(LidarOdometryOptions(), 5);
  std::printf("12 m gap after the first scan: across %.4f m, the pair after it %.4f m\n", now[0],
              now[1]);
  EXPECT_LT(now[0], 0.05) << "across the gap (12 m)";
  EXPECT_LT(now[1], 0.05) << "the pair after it";
}

}  // namespace
}  // namespace lidar
}  // namespace plucker
