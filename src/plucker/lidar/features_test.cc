#include "plucker/lidar/features.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <set>

#include "plucker/sim/lidar_scene.h"
#include "plucker/sim/lidar_sim.h"

namespace plucker {
namespace lidar {
namespace {

bool ExtractFeatures(const LidarScan& scan, const FeatureOptions& options, ScanFeatures* features,
                     std::string* error) {
  return FeatureExtractor().Extract(scan, options, features, error);
}

// One horizontal ring (ring 0) sampled every `step_deg` of azimuth through `range_of(azimuth)`.
template <typename F>
LidarScan Ring(double step_deg, F range_of) {
  LidarScan scan;
  const int n = static_cast<int>(std::round(360.0 / step_deg));
  for (int i = 0; i < n; ++i) {
    const double az = M_PI - 2.0 * M_PI * i / n;
    const double r = range_of(az);
    scan.points.emplace_back(r * std::cos(az), r * std::sin(az), 0.0);
    scan.ring.push_back(0);
  }
  return scan;
}

// A square room seen from its centre: walls at |x| = 10 and |y| = 10 (corners at 45 deg).
double SquareRoom(double az) {
  return 10.0 / std::max(std::abs(std::cos(az)), std::abs(std::sin(az)));
}

// The first scan of the simulated urban drive: 32 beams from -25 to +10 deg, 1000 firings per
// revolution.
LidarScan SimulatedUrbanScan() {
  const sim::LidarScene scene = sim::MakeUrbanScene();
  const sim::VehicleTrajectory trajectory(scene.route);
  sim::LidarSimOptions beams;
  for (int b = 0; b < 32; ++b) beams.elevation_rad.push_back((-25.0 + 35.0 * b / 31) * M_PI / 180);
  beams.azimuth_steps = 1000;
  return sim::LidarSimulator(scene, beams).Scan(trajectory, 0.0, 0);
}

bool NearCorner(const Eigen::Vector3d& p, double tol) {
  return std::abs(std::abs(p.x()) - 10.0) < tol && std::abs(std::abs(p.y()) - 10.0) < tol;
}

TEST(FeaturesTest, CornersGiveEdgesAndWallsGivePlanes) {
  const LidarScan scan = Ring(0.2, SquareRoom);
  FeatureOptions options;
  options.edge_voxel_size = 0.0;
  options.plane_voxel_size = 0.0;
  options.sectors = 4;
  ScanFeatures f;
  std::string error;
  ASSERT_TRUE(ExtractFeatures(scan, options, &f, &error)) << error;
  EXPECT_EQ(f.stats.rings, 1);
  // The four corners are the strongest edges; every sharp point lies at a corner.
  ASSERT_GE(f.sharp.size(), 4u);
  for (const auto& p : f.sharp) EXPECT_TRUE(NearCorner(p, 0.5)) << p.transpose();
  int corners_found = 0;
  for (int c = 0; c < 4; ++c) {
    const Eigen::Vector3d corner(c % 2 ? 10 : -10, c / 2 ? 10 : -10, 0);
    for (const auto& p : f.sharp) {
      if ((p - corner).norm() < 0.5) {
        ++corners_found;
        break;
      }
    }
  }
  EXPECT_EQ(corners_found, 4);
  // Flat points lie on walls, away from the corners.
  ASSERT_GE(f.flat.size(), 8u);
  for (const auto& p : f.flat) {
    EXPECT_NEAR(std::max(std::abs(p.x()), std::abs(p.y())), 10.0, 1e-9);
    EXPECT_FALSE(NearCorner(p, 0.5)) << p.transpose();
  }
  EXPECT_GT(f.planes.size(), f.flat.size());
  for (const auto& p : f.planes)
    EXPECT_NEAR(std::max(std::abs(p.x()), std::abs(p.y())), 10.0, 1e-9);
}

TEST(FeaturesTest, OccludedSideOfADepthJumpIsRejected) {
  // A wall at 20 m with a 2 m wide pillar at 5 m in front of it (azimuth 80..100 deg... here a
  // narrow sector around +90 deg).
  auto range_of = [](double az) {
    const double pillar_half = 6.0 * M_PI / 180.0;
    if (std::abs(az - M_PI / 2) < pillar_half) return 5.0;
    return 20.0;
  };
  const LidarScan scan = Ring(0.2, range_of);
  FeatureOptions options;
  options.edge_voxel_size = 0.0;
  ScanFeatures f;
  std::string error;
  ASSERT_TRUE(ExtractFeatures(scan, options, &f, &error)) << error;
  EXPECT_GE(f.stats.occluded_rejected, 2 * options.curvature_half_window);
  // No edge is reported on the far wall next to the pillar (the occluded side), while the
  // pillar's own boundary points (5 m) are edges.
  bool pillar_edge = false;
  for (const auto& p : f.edges) {
    const double r = p.norm();
    if (std::abs(r - 5.0) < 1e-6) pillar_edge = true;
    const double az = std::atan2(p.y(), p.x());
    if (std::abs(r - 20.0) < 1e-6) {
      EXPECT_GT(std::abs(az - M_PI / 2), 6.0 * M_PI / 180.0 + 6 * 0.2 * M_PI / 180.0)
          << "edge on the occluded wall at azimuth " << az;
    }
  }
  EXPECT_TRUE(pillar_edge);
}

TEST(FeaturesTest, SurfaceParallelToTheBeamIsRejected) {
  // A wall at y = 2 m seen at grazing angles (azimuth 2..12 deg): consecutive returns are far
  // apart compared with their range (LOAM's criterion); elsewhere a circle at 30 m.
  auto range_of = [](double az) {
    const double s = std::sin(az);
    if (az > 2.0 * M_PI / 180 && az < 12.0 * M_PI / 180) return 2.0 / s;
    return 30.0;
  };
  const LidarScan scan = Ring(0.2, range_of);
  FeatureOptions options;
  ScanFeatures f;
  std::string error;
  ASSERT_TRUE(ExtractFeatures(scan, options, &f, &error)) << error;
  EXPECT_GT(f.stats.parallel_rejected, 20);
  for (const auto& p : f.flat)
    EXPECT_NEAR(p.norm(), 30.0, 1e-9) << "flat point on the grazing wall";
}

TEST(FeaturesTest, RangeGatingNaNsAndBadInput) {
  LidarScan scan = Ring(0.5, SquareRoom);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  scan.points[10] = Eigen::Vector3d(nan, 0, 0);
  scan.points[20] = Eigen::Vector3d(0.1, 0.1, 0);  // closer than min_range
  FeatureOptions options;
  ScanFeatures f;
  std::string error;
  ASSERT_TRUE(ExtractFeatures(scan, options, &f, &error)) << error;
  EXPECT_EQ(f.stats.valid_points, static_cast<int>(scan.size()) - 2);
  for (const auto& p : f.planes) EXPECT_TRUE(p.allFinite());

  LidarScan no_rings = scan;
  no_rings.ring.clear();
  EXPECT_FALSE(ExtractFeatures(no_rings, options, &f, &error));
  EXPECT_NE(error.find("ring"), std::string::npos);
  EXPECT_FALSE(ExtractFeatures(LidarScan(), options, &f, &error));
  LidarScan far = scan;
  for (auto& p : far.points) p *= 1000.0;  // everything beyond max_range
  EXPECT_FALSE(ExtractFeatures(far, options, &f, &error));
  EXPECT_NE(error.find("valid"), std::string::npos);
}

// Rings need not come in runs: two rings fired alternately give the same features as the same
// rings one after the other; unassigned points (-1) are skipped; a ring index past the limit in
// the middle of the scan is an error that names it.
TEST(FeaturesTest, InterleavedRingsUnassignedPointsAndBadRingIndex) {
  const LidarScan ring = Ring(0.5, SquareRoom);
  LidarScan runs = ring, interleaved;
  for (std::size_t i = 0; i < ring.size(); ++i) {  // ring 1: the same ring 1 m higher
    runs.points.push_back(ring.points[i] + Eigen::Vector3d(0, 0, 1));
    runs.ring.push_back(1);
    for (int r = 0; r < 2; ++r) {
      interleaved.points.push_back(ring.points[i] + Eigen::Vector3d(0, 0, r));
      interleaved.ring.push_back(r);
    }
  }
  FeatureOptions options;
  ScanFeatures a, b;
  std::string error;
  ASSERT_TRUE(ExtractFeatures(runs, options, &a, &error)) << error;
  ASSERT_TRUE(ExtractFeatures(interleaved, options, &b, &error)) << error;
  EXPECT_EQ(a.stats.rings, 2);
  ASSERT_GT(a.planes.size(), 100u);
  EXPECT_EQ(a.planes, b.planes);
  EXPECT_EQ(a.edges, b.edges);
  EXPECT_EQ(a.stats.valid_points, b.stats.valid_points);

  for (std::size_t i = 0; i < 10; ++i) interleaved.ring[2 * i + 1] = -1;  // 10 points of ring 1
  ASSERT_TRUE(ExtractFeatures(interleaved, options, &b, &error)) << error;
  EXPECT_EQ(b.stats.valid_points, a.stats.valid_points - 10);
  interleaved.ring[interleaved.size() / 2] = 5000;
  EXPECT_FALSE(ExtractFeatures(interleaved, options, &b, &error));
  EXPECT_NE(error.find("ring index 5000"), std::string::npos) << error;
}

TEST(FeaturesTest, TimesFromAzimuthSpanOneRevolution) {
  const LidarScan scan = Ring(0.2, SquareRoom);
  FeatureOptions options;
  options.compute_times = true;
  options.plane_voxel_size = 0.0;
  ScanFeatures f;
  std::string error;
  ASSERT_TRUE(ExtractFeatures(scan, options, &f, &error)) << error;
  EXPECT_TRUE(f.stats.times_from_azimuth);
  ASSERT_EQ(f.plane_times.size(), f.planes.size());
  double lo = 1, hi = 0;
  for (std::size_t i = 0; i < f.planes.size(); ++i) {
    // The ring starts at azimuth pi and turns clockwise: t = period * swept / (2 pi).
    const double az = std::atan2(f.planes[i].y(), f.planes[i].x());
    double swept = M_PI - az;
    if (swept < 0) swept += 2 * M_PI;
    EXPECT_NEAR(f.plane_times[i], 0.1 * swept / (2 * M_PI), 1e-6);
    lo = std::min(lo, f.plane_times[i]);
    hi = std::max(hi, f.plane_times[i]);
  }
  EXPECT_LT(lo, 0.005);
  EXPECT_GT(hi, 0.095);
}

TEST(FeaturesTest, VoxelDownsampleKeepsOnePointPerVoxel) {
  std::vector<Eigen::Vector3d> pts;
  std::vector<double> times;
  for (int i = 0; i < 100; ++i) {
    pts.emplace_back(0.01 * i, 0.0, 0.0);  // 1 m of points every 1 cm
    times.push_back(i);
  }
  VoxelDownsample(0.25, &pts, &times);
  EXPECT_EQ(pts.size(), 4u);
  EXPECT_EQ(times.size(), 4u);
  EXPECT_DOUBLE_EQ(times[1], 25.0);
}

// Thousands of voxels (the key table grows from 1024 slots several times, reinserting its keys),
// negative coordinates, revisits in any order: the first point of each voxel, in input order.
TEST(FeaturesTest, VoxelDownsampleMatchesAReferenceThroughTableGrowth) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-6.0, 6.0);
  std::vector<Eigen::Vector3d> pts;
  std::vector<double> times;
  for (int i = 0; i < 6000; ++i) {
    pts.emplace_back(u(rng), u(rng), 0.1 * u(rng));
    times.push_back(i);
  }
  std::vector<Eigen::Vector3d> expected;
  std::vector<double> expected_times;
  std::set<std::array<long, 3>> seen;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector3d v = (pts[i] / 0.25).array().floor();
    if (seen.insert({std::lround(v.x()), std::lround(v.y()), std::lround(v.z())}).second) {
      expected.push_back(pts[i]);
      expected_times.push_back(times[i]);
    }
  }
  VoxelDownsample(0.25, &pts, &times);
  EXPECT_GT(expected.size(), 3000u);  // more than 1024 / 2 slots many times over
  EXPECT_LT(expected.size(), 6000u);  // and some voxels visited again
  EXPECT_EQ(pts, expected);
  EXPECT_EQ(times, expected_times);
}

void ExpectSameFeatures(const ScanFeatures& a, const ScanFeatures& b) {
  EXPECT_EQ(a.sharp, b.sharp);
  EXPECT_EQ(a.edges, b.edges);
  EXPECT_EQ(a.flat, b.flat);
  EXPECT_EQ(a.planes, b.planes);
  EXPECT_EQ(a.edge_times, b.edge_times);
  EXPECT_EQ(a.plane_times, b.plane_times);
  EXPECT_EQ(a.stats.occluded_rejected, b.stats.occluded_rejected);
  EXPECT_EQ(a.stats.valid_points, b.stats.valid_points);
}

// The extractor keeps its buffers from scan to scan: a scan must come out as from a fresh
// extraction whatever came before it (a larger scan, a smaller one, a failed one).
TEST(FeaturesTest, ExtractorReusedAcrossScansMatchesFreshExtraction) {
  const LidarScan urban = SimulatedUrbanScan();
  const LidarScan room = Ring(0.2, SquareRoom);
  FeatureOptions options;
  options.compute_times = true;
  std::string error;
  ScanFeatures fresh_urban, fresh_room;
  ASSERT_TRUE(ExtractFeatures(urban, options, &fresh_urban, &error)) << error;
  ASSERT_TRUE(ExtractFeatures(room, options, &fresh_room, &error)) << error;
  ASSERT_GT(fresh_urban.planes.size(), 1000u);
  FeatureExtractor extractor;
  ScanFeatures f;
  int compared = 0;
  for (int pass = 0; pass < 2; ++pass) {
    ASSERT_TRUE(extractor.Extract(urban, options, &f, &error)) << error;
    ExpectSameFeatures(f, fresh_urban);
    ASSERT_TRUE(extractor.Extract(room, options, &f, &error)) << error;
    ExpectSameFeatures(f, fresh_room);
    EXPECT_FALSE(extractor.Extract(LidarScan(), options, &f, &error));
    EXPECT_TRUE(f.planes.empty());
    compared += 2;
  }
  EXPECT_EQ(compared, 4);
}

TEST(FeaturesTest, SyntheticUrbanScanHasEdgesAndPlanes) {
  const LidarScan scan = SimulatedUrbanScan();
  ScanFeatures f;
  std::string error;
  ASSERT_TRUE(ExtractFeatures(scan, FeatureOptions(), &f, &error)) << error;
  EXPECT_EQ(f.stats.rings, 32);
  EXPECT_GT(f.stats.sharp, 50);
  EXPECT_GT(f.stats.planes, 1000);
}

}  // namespace
}  // namespace lidar
}  // namespace plucker
