// The odometry on the sensors other than the HDL-64E, on distorted sweeps of an accelerating
// vehicle (ground truth from the simulator): per-point time against the constant-velocity
// deskew from the azimuth and against no deskew; the generic (ring-less) mode with and without
// per-point time, and its start at speed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "plucker/lidar/odometry.h"
#include "plucker/sensor/lidar_model.h"
#include "plucker/sim/lidar_scene.h"
#include "plucker/sim/lidar_sim.h"

namespace plucker {
namespace lidar {
namespace {

enum class Time { kPerPoint, kDropped };

// Mean relative translation error (m) over the frames - 1 pairs of `model` driving the street
// grid at 10 +- 6 m/s (accelerations up to 9.4 m/s^2) through its first corner.
double MeanRelativeError(const sensor::LidarModel& model, Time time, DeskewMode deskew,
                         double speed_variation = 6.0, int frames = 12) {
  const sim::LidarScene scene = sim::MakeUrbanScene();
  sim::VehicleTrajectoryOptions motion;
  motion.speed_variation = speed_variation;
  const sim::VehicleTrajectory trajectory(scene.route, motion);
  const sim::LidarSimOptions o = sim::LidarSimOptionsFor(model, 0.01, true);
  const sim::LidarSimulator simulator(scene, o);
  LidarOdometryOptions options;
  options.sensor = model.spinning ? "auto" : "generic";
  options.deskew = deskew;
  LidarOdometry odometry(options);
  std::vector<SE3d> T_w_s_gt;
  for (int i = 0; i < frames; ++i) {
    const double t0 = 0.1 * i;
    T_w_s_gt.push_back(trajectory.T_w_s(t0));
    LidarScan scan = simulator.Scan(trajectory, t0, i);
    if (time == Time::kDropped) scan.time.clear();
    const FrameResult r = odometry.ProcessScan(std::move(scan));
    EXPECT_TRUE(r.ok) << model.name << " frame " << i << ": " << r.error;
  }
  double sum = 0.0;
  const auto& est = odometry.poses();
  for (std::size_t i = 1; i < est.size(); ++i) {
    const SE3d gt = T_w_s_gt[i - 1].Inverse() * T_w_s_gt[i];
    sum += (gt.Inverse() * (est[i - 1].Inverse() * est[i])).translation().norm();
  }
  return sum / static_cast<double>(est.size() - 1);
}

TEST(LidarOdometrySensorTest, Os1PerPointTimeDeskewsAnAcceleratingSweep) {
  const sensor::LidarModel os1 = sensor::OS1_64();
  const double per_point = MeanRelativeError(os1, Time::kPerPoint, DeskewMode::kAuto);
  const double azimuth = MeanRelativeError(os1, Time::kDropped, DeskewMode::kOn);
  const double off = MeanRelativeError(os1, Time::kPerPoint, DeskewMode::kOff);
  std::printf(
      "os1-64, mean relative translation error: per-point time %.4f m, azimuth %.4f m, "
      "no deskew %.4f m\n",
      per_point, azimuth, off);
  EXPECT_LT(per_point, 0.03);
  EXPECT_LT(per_point, 0.7 * off);
  EXPECT_LT(azimuth, 0.7 * off);  // the sim fires in azimuth order: both times agree
}

TEST(LidarOdometrySensorTest, GenericModeNeedsPerPointTimeOnAMovingSweep) {
  const sensor::LidarModel generic = sensor::GenericLidar();
  // 10 +- 2 m/s (up to 3.1 m/s^2).
  const double with_time = MeanRelativeError(generic, Time::kPerPoint, DeskewMode::kAuto, 2.0);
  const double without = MeanRelativeError(generic, Time::kDropped, DeskewMode::kAuto, 2.0);
  std::printf("generic, mean relative translation error: per-point time %.4f m, none %.4f m\n",
              with_time, without);
  EXPECT_LT(with_time, 0.05);
  EXPECT_LT(with_time, 0.7 * without);
}

// A start at speed in generic mode, 10 +- 6 m/s: the sweep-motion search has to find the first
// sweeps' forward motion (~1 m) and yaw (~5 deg) alone. Measured 1.2 cm (2026-12-03); scored by
// the plane count (before), the search found ~0 m of the 1 m: 1.07 m (sweep_motion.h).
TEST(LidarOdometrySensorTest, GenericModeStartsAtSpeed) {
  const double error =
      MeanRelativeError(sensor::GenericLidar(), Time::kPerPoint, DeskewMode::kAuto, 6.0, 4);
  std::printf("generic at 10 +- 6 m/s, first 3 pairs: mean relative translation error %.4f m\n",
              error);
  EXPECT_LT(error, 0.03);
}

}  // namespace
}  // namespace lidar
}  // namespace plucker
