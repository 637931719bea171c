#include "plucker/sim/lidar_sim.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <set>

#include "plucker/sensor/lidar_model.h"

namespace plucker {
namespace sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

// The HDL-64E pattern of sensor/lidar_model.h.
LidarSimOptions Hdl64Options(int azimuth_steps = 2083) {
  const sensor::LidarModel hdl64 = sensor::HDL64();
  LidarSimOptions o;
  o.elevation_rad = hdl64.elevation_rad;
  o.azimuth_steps = azimuth_steps;
  o.min_range = hdl64.min_range;
  o.max_range = hdl64.max_range;
  return o;
}

class LidarSimTest : public ::testing::Test {
 protected:
  LidarSimTest() : scene_(MakeUrbanScene()), traj_(scene_.route) {}
  LidarScene scene_;
  VehicleTrajectory traj_;
};

TEST_F(LidarSimTest, TrajectoryIsSmoothAtConstantSpeed) {
  EXPECT_GT(traj_.loop_length(), 1000.0);
  const double dt = 0.01;
  for (double t = 0; t < traj_.loop_duration(); t += 0.37) {
    const SE3d a = traj_.T_w_s(t), b = traj_.T_w_s(t + dt);
    EXPECT_NEAR((b.translation() - a.translation()).norm() / dt, 10.0, 1e-3) << t;
    EXPECT_LT(std::abs(2 * std::acos(std::min(
                               1.0, std::abs((a.rotation().conjugate() * b.rotation()).w())))),
              0.02);  // < 2 rad/s yaw rate
    EXPECT_NEAR(a.translation().z(), 1.73, 1e-12);
  }
  // The loop closes.
  EXPECT_LT(
      (traj_.T_w_s(0).translation() - traj_.T_w_s(traj_.loop_duration()).translation()).norm(),
      1e-6);
}

TEST_F(LidarSimTest, BeamsRingsAndGeometry) {
  const LidarSimOptions o = Hdl64Options();
  const LidarSimulator sim(scene_, o);
  LidarSimStats stats;
  const auto start = std::chrono::steady_clock::now();
  const std::clock_t cpu_start = std::clock();
  const LidarScan scan = sim.Scan(traj_, 2.0, 0, &stats);
  const double cpu_ms = 1e3 * static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::printf("HDL-64 scan: %zu rays, %zu points, %.1f ms CPU (%.1f ms wall)\n", stats.rays,
              stats.hits, cpu_ms, ms);
  EXPECT_EQ(stats.rays, 64u * 2083u);
  EXPECT_GT(scan.size(), 60000u);
  ASSERT_EQ(scan.ring.size(), scan.size());
  ASSERT_EQ(scan.intensity.size(), scan.size());
  EXPECT_TRUE(scan.time.empty());
  EXPECT_EQ(std::set<int>(scan.ring.begin(), scan.ring.end()).size(), 64u);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const Eigen::Vector3d& p = scan.points[i];
    const double el = std::atan2(p.z(), p.head<2>().norm());
    ASSERT_NEAR(el, o.elevation_rad[scan.ring[i]], 1e-9);
    ASSERT_GE(p.norm(), o.min_range);
    ASSERT_LE(p.norm(), o.max_range);
    if (i > 0) {
      ASSERT_GE(scan.ring[i], scan.ring[i - 1]);  // ring by ring
    }
  }
  // Points are on the scene: re-casting from the pose along each point hits at its range.
  const SE3d T_w_s = traj_.T_w_s(2.0);
  for (std::size_t i = 0; i < scan.size(); i += 997) {
    const Eigen::Vector3d d_w = T_w_s.RotationMatrix() * scan.points[i].normalized();
    const auto hit = scene_.Cast(T_w_s.translation(), d_w, o.min_range, o.max_range);
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(hit->distance, scan.points[i].norm(), 1e-9);
  }
}

TEST_F(LidarSimTest, NoiseStatisticsAndDeterminism) {
  LidarSimOptions o = Hdl64Options(500);
  const LidarScan clean = LidarSimulator(scene_, o).Scan(traj_, 5.0, 3);
  o.range_noise_sigma = 0.05;
  const LidarScan noisy = LidarSimulator(scene_, o).Scan(traj_, 5.0, 3);
  const LidarScan again = LidarSimulator(scene_, o).Scan(traj_, 5.0, 3);
  ASSERT_EQ(clean.size(), noisy.size());  // no point crosses a range limit here
  double sum = 0, sum2 = 0;
  for (std::size_t i = 0; i < clean.size(); ++i) {
    const double e = noisy.points[i].norm() - clean.points[i].norm();
    sum += e;
    sum2 += e * e;
    EXPECT_NEAR(noisy.points[i].normalized().dot(clean.points[i].normalized()), 1.0, 1e-12);
  }
  const double n = static_cast<double>(clean.size());
  const double mean = sum / n, sigma = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 4 * 0.05 / std::sqrt(n));
  EXPECT_NEAR(sigma, 0.05, 0.05 * 0.03);
  // Deterministic per seed and frame; another frame index or seed draws other noise.
  ASSERT_EQ(again.size(), noisy.size());
  for (std::size_t i = 0; i < noisy.size(); ++i) ASSERT_EQ(again.points[i], noisy.points[i]);
  const LidarScan other_frame = LidarSimulator(scene_, o).Scan(traj_, 5.0, 4);
  o.seed = 2;
  const LidarScan other_seed = LidarSimulator(scene_, o).Scan(traj_, 5.0, 3);
  EXPECT_NE(other_frame.points[10], noisy.points[10]);
  EXPECT_NE(other_seed.points[10], noisy.points[10]);
}

TEST_F(LidarSimTest, DistortionTimesAndPoses) {
  LidarSimOptions o = Hdl64Options(720);
  o.distortion = true;
  const double t0 = 7.0;
  const LidarScan scan = LidarSimulator(scene_, o).Scan(traj_, t0, 0);
  ASSERT_EQ(scan.time.size(), scan.size());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    ASSERT_GE(scan.time[i], 0.0);
    ASSERT_LT(scan.time[i], 0.1);
    // Time grows with the azimuth (counter-clockwise from the front) within a ring.
    const double az = std::atan2(scan.points[i].y(), scan.points[i].x());
    const double az_ccw = az < 0 ? az + 2 * M_PI : az;
    EXPECT_NEAR(az_ccw / (2 * M_PI) * 0.1, scan.time[i], 0.1 / 720 + 1e-9);
    if (i > 0 && scan.ring[i] == scan.ring[i - 1]) {
      ASSERT_GE(scan.time[i], scan.time[i - 1]);
    }
  }
  // Each point lies on the scene as seen from the pose at its own firing time.
  for (std::size_t i = 0; i < scan.size(); i += 311) {
    const SE3d T = traj_.T_w_s(t0 + scan.time[i]);
    const auto hit = scene_.Cast(T.translation(), T.RotationMatrix() * scan.points[i].normalized(),
                                 o.min_range, o.max_range);
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(hit->distance, scan.points[i].norm(), 1e-9);
  }
}

TEST(LidarSimCorridor, ScansTheTunnel) {
  const LidarScene scene = MakeCorridorScene();
  const VehicleTrajectory traj(scene.route);
  const LidarScan scan = LidarSimulator(scene, Hdl64Options(360)).Scan(traj, 10.0, 0);
  EXPECT_GT(scan.size(), 64u * 300u);  // closed tunnel: almost every ray returns
}

TEST(LidarSimOptionsCheck, RejectsInvalid) {
  const LidarScene scene = MakeCorridorScene();
  LidarSimOptions o;
  EXPECT_THROW(LidarSimulator(scene, o), std::invalid_argument);  // no beams
  EXPECT_THROW(VehicleTrajectory({Eigen::Vector2d(0, 0)}), std::invalid_argument);
}

}  // namespace
}  // namespace sim
}  // namespace plucker
