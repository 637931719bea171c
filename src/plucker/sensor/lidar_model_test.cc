#include "plucker/sensor/lidar_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "plucker/io/kitti_lidar.h"
#include "plucker/sim/lidar_scene.h"
#include "plucker/sim/lidar_sim.h"

namespace plucker {
namespace sensor {
namespace {

namespace fs = std::filesystem;
constexpr double kDeg = M_PI / 180.0;

sim::LidarSimOptions SimOptions(const LidarModel& m) {
  sim::LidarSimOptions o;
  o.elevation_rad = m.elevation_rad;
  o.azimuth_steps = m.azimuth_steps / 2;  // half resolution: fast enough for a unit test
  o.min_range = m.min_range;
  o.max_range = m.max_range;
  return o;
}

LidarScan Simulate(const LidarModel& m) {
  const sim::LidarScene scene = sim::MakeUrbanScene();
  const sim::VehicleTrajectory traj(scene.route);
  return sim::LidarSimulator(scene, SimOptions(m)).Scan(traj, 3.0, 0);
}

TEST(LidarModel, Tables) {
  for (const LidarModel& m : {HDL64(), VLP32(), VLP16()}) {
    ASSERT_GT(m.num_rings(), 1) << m.name;
    for (int r = 1; r < m.num_rings(); ++r) {
      EXPECT_GT(m.elevation_rad[r], m.elevation_rad[r - 1]) << m.name << " ring " << r;
    }
    EXPECT_EQ(LidarModelFromName(m.name).name, m.name);
  }
  EXPECT_EQ(HDL64().num_rings(), 64);
  EXPECT_NEAR(HDL64().elevation_rad.front(), -24.33 * kDeg, 1e-12);
  EXPECT_NEAR(HDL64().elevation_rad.back(), 2.0 * kDeg, 1e-12);
  EXPECT_EQ(VLP32().num_rings(), 32);
  EXPECT_NEAR(VLP32().elevation_rad.front(), -25.0 * kDeg, 1e-12);
  EXPECT_NEAR(VLP32().elevation_rad.back(), 15.0 * kDeg, 1e-12);
  EXPECT_EQ(VLP16().num_rings(), 16);
  EXPECT_NEAR(VLP16().elevation_rad[8], 1.0 * kDeg, 1e-12);
  EXPECT_EQ(LidarModelFromName("HDL64").name, "hdl64");
  EXPECT_THROW(LidarModelFromName("ouster"), std::invalid_argument);
}

TEST(LidarModel, RingFromElevation) {
  const LidarModel m = VLP16();
  for (int r = 0; r < 16; ++r) {
    EXPECT_EQ(m.RingFromElevation(m.elevation_rad[r]), r);
    EXPECT_EQ(m.RingFromElevation(m.elevation_rad[r] + 0.9 * kDeg), r);
    EXPECT_EQ(m.RingFromElevation(m.elevation_rad[r] - 0.9 * kDeg), r);
  }
  EXPECT_EQ(m.RingFromElevation(-15.9 * kDeg), 0);
  EXPECT_EQ(m.RingFromElevation(-16.1 * kDeg), -1);
  EXPECT_EQ(m.RingFromElevation(16.1 * kDeg), -1);
  EXPECT_EQ(m.RingFromElevation(std::nan("")), -1);
}

TEST(LidarModel, AssignRingsOnSimulatedScans) {
  for (const LidarModel& m : {HDL64(), VLP32(), VLP16()}) {
    LidarScan scan = Simulate(m);
    const std::vector<int> rings_gt = scan.ring;
    scan.ring.clear();
    const RingAssignmentStats stats = AssignRings(&scan, m);
    EXPECT_EQ(stats.unassigned, 0u) << m.name;
    EXPECT_EQ(stats.rings_found, m.num_rings()) << m.name;
    EXPECT_EQ(scan.ring, rings_gt) << m.name;
    // An existing ring field is kept.
    scan.ring.assign(scan.size(), 3);
    EXPECT_EQ(AssignRings(&scan, m).rings_found, 1);
  }
}

TEST(LidarModel, ScanOrderRingsOnSimulatedScans) {
  LidarScan scan = Simulate(HDL64());
  const std::vector<int> rings_gt = scan.ring;
  // Reverse the ring blocks (top beam first, as in KITTI): ring 0 must still be the lowest.
  const RingAssignmentStats stats = AssignRingsFromScanOrder(&scan);
  EXPECT_EQ(stats.rings_found, 64);
  EXPECT_EQ(scan.ring, rings_gt);
}

TEST(LidarModel, AutoDetectOnSimulatedScans) {
  for (const LidarModel& m : {HDL64(), VLP32(), VLP16()}) {
    double confidence = 0;
    EXPECT_EQ(AutoDetectSensor(Simulate(m), &confidence).name, m.name);
    EXPECT_GT(confidence, 0.5) << m.name;
  }
  double confidence = 1;
  AutoDetectSensor(LidarScan(), &confidence);
  EXPECT_EQ(confidence, 0.0);
}

TEST(LidarModel, RealKittiScans) {
  const fs::path dir =
      fs::path(PLUCKER_SHARED_DATA_DIR) / "kitti-odometry-00/sequences/00/velodyne";
  if (!fs::exists(dir / "000000.bin")) GTEST_SKIP() << "no KITTI extract at " << dir;
  for (const char* name : {"000000.bin", "000015.bin"}) {
    LidarScan scan = io::ReadKittiBin((dir / name).string());
    LidarScan by_elevation = scan;
    const RingAssignmentStats order = AssignRingsFromScanOrder(&scan);
    EXPECT_GE(order.rings_found, 62) << name;
    EXPECT_LE(order.rings_found, 66) << name;
    std::map<int, std::size_t> count;
    std::map<int, double> elevation;
    for (std::size_t i = 0; i < scan.size(); ++i) {
      ++count[scan.ring[i]];
      elevation[scan.ring[i]] += std::atan2(scan.points[i].z(), scan.points[i].head<2>().norm());
    }
    std::size_t typical = 0;
    for (const auto& [ring, n] : count) typical += (n >= 1500 && n <= 2200);
    EXPECT_GE(typical, 50u) << name;  // near-empty rings: sky/vehicle-masked beams
    // Ring 0 is the lowest beam.
    EXPECT_LT(elevation[0] / count[0],
              elevation[order.rings_found - 1] / count[order.rings_found - 1]);
    // Elevation rings agree with scan-order rings for most points (the table is approximate).
    const RingAssignmentStats el = AssignRings(&by_elevation, HDL64());
    EXPECT_GE(el.rings_found, 60) << name;
    // On KITTI the measured elevations lie ~0.5 deg above the approximate table (about one ring).
    std::size_t agree1 = 0, agree2 = 0;
    for (std::size_t i = 0; i < scan.size(); ++i) {
      agree1 += std::abs(scan.ring[i] - by_elevation.ring[i]) <= 1;
      agree2 += std::abs(scan.ring[i] - by_elevation.ring[i]) <= 2;
    }
    std::printf("%s: %d scan-order rings; elevation rings within 1: %.1f%%, within 2: %.1f%%\n",
                name, order.rings_found, 100.0 * agree1 / scan.size(),
                100.0 * agree2 / scan.size());
    EXPECT_GT(static_cast<double>(agree2) / scan.size(), 0.7) << name;
    double confidence = 0;
    EXPECT_EQ(AutoDetectSensor(scan, &confidence).name, "hdl64") << name;
  }
}

}  // namespace
}  // namespace sensor
}  // namespace plucker
