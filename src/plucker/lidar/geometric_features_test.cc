// Features without rings (sensor generic): local geometry on synthetic structures and on the
// simulator's non-spinning sensor, and the sensor check that refuses such a cloud as an HDL-64E.
#include "plucker/lidar/geometric_features.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "plucker/lidar/sensor_check.h"
#include "plucker/sensor/lidar_model.h"
#include "plucker/sim/lidar_scene.h"
#include "plucker/sim/lidar_sim.h"

namespace plucker {
namespace lidar {
namespace {

LidarScan Simulate(const sensor::LidarModel& m, bool distortion = false) {
  const sim::LidarScene scene = sim::MakeUrbanScene();
  const sim::VehicleTrajectory trajectory(scene.route);
  return sim::LidarSimulator(scene, sim::LidarSimOptionsFor(m, 0.01, distortion))
      .Scan(trajectory, 3.0, 0);
}

// A ground plane z = -1.7 (10 x 10 m), a vertical pole at (5, 0) and random clutter, shuffled:
// no ring, no order.
TEST(GeometricFeatures, PlanesOnTheGroundEdgesOnThePole) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  LidarScan scan;
  for (int i = 0; i < 20000; ++i) scan.points.emplace_back(5.0 * u(rng) + 6.0, 5.0 * u(rng), -1.7);
  for (int i = 0; i < 600; ++i) scan.points.emplace_back(3.0, 3.0, 3.0 * u(rng) + 1.3);
  std::shuffle(scan.points.begin(), scan.points.end(), rng);
  GeometricFeatureExtractor extractor;
  ScanFeatures f;
  std::string error;
  FeatureOptions ring_options;
  ASSERT_TRUE(extractor.Extract(scan, ring_options, GeometricFeatureOptions(), &f, &error))
      << error;
  ASSERT_GT(f.planes.size(), 100u);
  for (const auto& p : f.planes) EXPECT_NEAR(p.z(), -1.7, 1e-9);
  // Edges: mostly on the pole; the rest are elongated neighbourhoods of the random ground
  // sampling (an edge is tested before a plane: geometric_features.cc). Measured 27 of 48.
  int on_pole = 0;
  for (const auto& p : f.edges) on_pole += (p.head<2>() - Eigen::Vector2d(3, 3)).norm() < 1e-9;
  EXPECT_GE(on_pole, 10);
  EXPECT_GE(on_pole, 0.5 * static_cast<double>(f.edges.size()));
  EXPECT_EQ(f.stats.edges, static_cast<int>(f.edges.size()));
  EXPECT_GT(f.stats.valid_points, 0.99 * static_cast<double>(scan.size()));  // a few < 2 m
}

// The plane information (the sweep-motion search's score, sweep_motion.h): a ground plane and a
// wall across x constrain z and x, nothing constrains y; the features are the same with it.
TEST(GeometricFeatures, PlaneInformationFollowsTheNormals) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  LidarScan scan;
  for (int i = 0; i < 20000; ++i) scan.points.emplace_back(4.0 * u(rng) + 4.0, 5.0 * u(rng), -1.7);
  for (int i = 0; i < 10000; ++i) scan.points.emplace_back(9.0, 5.0 * u(rng), 1.5 * u(rng));
  std::shuffle(scan.points.begin(), scan.points.end(), rng);
  GeometricFeatureExtractor extractor;
  ScanFeatures f, g;
  std::string error;
  Matrix6d info;
  ASSERT_TRUE(
      extractor.Extract(scan, FeatureOptions(), GeometricFeatureOptions(), &f, &error, &info))
      << error;
  ASSERT_TRUE(extractor.Extract(scan, FeatureOptions(), GeometricFeatureOptions(), &g, &error));
  EXPECT_EQ(f.planes, g.planes);
  EXPECT_EQ(f.edges, g.edges);
  EXPECT_TRUE(info.isApprox(info.transpose()));
  const double x = info(3, 3), y = info(4, 4), z = info(5, 5);  // tangent (dtheta, dt)
  EXPECT_GT(x, 10.0);
  EXPECT_GT(z, 10.0);
  EXPECT_LT(y, 1e-3 * std::min(x, z));
  // Rotation about z moves the wall's points along x (lever arm y): information there too.
  EXPECT_GT(info(2, 2), 1.0);
}

TEST(GeometricFeatures, BadInputIsNamed) {
  GeometricFeatureExtractor extractor;
  ScanFeatures f;
  std::string error;
  LidarScan scan;
  scan.points.assign(4, Eigen::Vector3d(5, 0, 0));
  EXPECT_FALSE(extractor.Extract(scan, FeatureOptions(), GeometricFeatureOptions(), &f, &error));
  EXPECT_NE(error.find("too few valid points"), std::string::npos) << error;
  scan.points.assign(100, Eigen::Vector3d(5, 0, 0));
  scan.time.assign(3, 0.0);
  EXPECT_FALSE(extractor.Extract(scan, FeatureOptions(), GeometricFeatureOptions(), &f, &error));
  EXPECT_NE(error.find("time channel"), std::string::npos) << error;
}

TEST(GeometricFeatures, SimulatedGenericScanHasBothKindsAndTimes) {
  const LidarScan scan = Simulate(sensor::GenericLidar(), true);
  ASSERT_GT(scan.size(), 10000u);
  EXPECT_TRUE(scan.ring.empty());
  ASSERT_EQ(scan.time.size(), scan.size());
  GeometricFeatureExtractor extractor;
  ScanFeatures f;
  std::string error;
  FeatureOptions ring_options;
  ring_options.compute_times = true;
  ASSERT_TRUE(extractor.Extract(scan, ring_options, GeometricFeatureOptions(), &f, &error));
  EXPECT_GT(f.planes.size(), 500u);
  EXPECT_GT(f.edges.size(), 20u);
  ASSERT_EQ(f.plane_times.size(), f.planes.size());
  ASSERT_EQ(f.edge_times.size(), f.edges.size());
  const auto [lo, hi] = std::minmax_element(f.plane_times.begin(), f.plane_times.end());
  EXPECT_GE(*lo, 0.0);
  EXPECT_LE(*hi, 0.1);
  EXPECT_GT(*hi - *lo, 0.05);  // the times span the sweep
}

TEST(SensorCheck, GenericCloudIsNoHdl64AndSpinningCloudsFit) {
  const LidarScan generic = Simulate(sensor::GenericLidar());
  const SensorCheck bad = CheckScanMatchesSensor(generic, sensor::HDL64());
  EXPECT_FALSE(bad.ok);
  EXPECT_NE(bad.reason.find("--sensor generic"), std::string::npos) << bad.reason;
  EXPECT_LT(bad.on_beam_fraction, 0.7);
  EXPECT_TRUE(CheckScanMatchesSensor(generic, sensor::GenericLidar()).ok);
  for (const sensor::LidarModel& m : {sensor::VLP16(), sensor::OS1_64(), sensor::HDL64()}) {
    LidarScan scan = Simulate(m);
    EXPECT_TRUE(CheckScanMatchesSensor(scan, m).ok) << m.name;  // ring field
    scan.ring.clear();                                          // KITTI .bin: firing order
    const SensorCheck c = CheckScanMatchesSensor(scan, m);
    EXPECT_TRUE(c.ok) << m.name << ": " << c.reason;
  }
  const LidarScan os1 = Simulate(sensor::OS1_128());
  const SensorCheck rings = CheckScanMatchesSensor(os1, sensor::VLP16());
  EXPECT_FALSE(rings.ok);
  EXPECT_NE(rings.reason.find("ring field goes up to 127"), std::string::npos) << rings.reason;
}

}  // namespace
}  // namespace lidar
}  // namespace plucker
