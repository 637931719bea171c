#include "plucker/sensor/lidar_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <tuple>

#include "plucker/geometry/fast_atan2.h"
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

TEST(LidarModel, OusterAndGeneric) {
  // The OS1 datasheet's vertical fields of view: 33.2 deg (64 beams), 45 deg (128 beams).
  for (const auto& [m, beams, half_fov] :
       {std::tuple{OS1_64(), 64, 16.6}, std::tuple{OS1_128(), 128, 22.5}}) {
    EXPECT_EQ(m.num_rings(), beams);
    EXPECT_TRUE(m.spinning);
    EXPECT_NEAR(m.elevation_rad.front(), -half_fov * kDeg, 1e-12);
    EXPECT_NEAR(m.elevation_rad.back(), half_fov * kDeg, 1e-12);
    for (int r = 1; r < m.num_rings(); ++r) {
      EXPECT_NEAR(m.elevation_rad[r] - m.elevation_rad[r - 1], 2 * half_fov / (beams - 1) * kDeg,
                  1e-12);
    }
    EXPECT_EQ(m.azimuth_steps, 1024);
    EXPECT_EQ(LidarModelFromName(m.name).name, m.name);
  }
  EXPECT_EQ(LidarModelFromName("OS1-128").name, "os1-128");
  const LidarModel g = LidarModelFromName("generic");
  EXPECT_FALSE(g.spinning);
  EXPECT_EQ(g.num_rings(), 0);
  EXPECT_GT(g.rays_per_scan, 0);
  EXPECT_LT(g.min_elevation_rad, g.max_elevation_rad);
  try {
    LidarModelFromName("livox");
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("os1-128"), std::string::npos) << e.what();
  }
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

// The definition of the split into rings (lidar_model.h) from every point's azimuth (FastAtan2),
// as AssignRingsFromScanOrder computed it before it took its decisions on the coordinates: the
// ring of every point. *second_pass: the seam was moved behind the first point; *direction: the
// sweep direction (+1 counter-clockwise), the sign most steps take.
std::vector<int> ReferenceRings(const std::vector<Eigen::Vector3d>& p,
                                const ScanOrderOptions& options, bool* second_pass,
                                double* direction) {
  auto wrap = [](double a) {  // into (-pi, pi]
    while (a > M_PI) a -= 2 * M_PI;
    while (a <= -M_PI) a += 2 * M_PI;
    return a;
  };
  std::vector<double> az;
  for (const Eigen::Vector3d& q : p) az.push_back(FastAtan2(q.y(), q.x()));
  long votes = 0;
  for (std::size_t i = 1; i < p.size(); ++i) {
    const double d = wrap(az[i] - az[i - 1]);
    votes += (d > 0.0) - (d < 0.0);
  }
  const double dir = *direction = votes >= 0 ? 1.0 : -1.0;
  auto split = [&](double a0) {
    auto u = [&](std::size_t i) {
      double v = dir * (az[i] - a0);
      while (v < 0) v += 2 * M_PI;
      while (v >= 2 * M_PI) v -= 2 * M_PI;
      return v;
    };
    std::vector<std::size_t> starts = {0};
    double reached = u(0), prev = u(0);
    for (std::size_t i = 1; i < p.size(); ++i) {
      const double cur = u(i);
      if (prev - cur > options.wrap_threshold_rad && reached > M_PI &&
          i - starts.back() >= static_cast<std::size_t>(options.min_points_per_ring)) {
        starts.push_back(i);
        reached = cur;
      } else {
        reached = std::max(reached, cur);
      }
      prev = cur;
    }
    return starts;
  };
  std::vector<std::size_t> starts = split(az[0]);
  double earliest = 0.0;
  for (std::size_t s : starts) earliest = std::min(earliest, dir * wrap(az[s] - az[0]));
  *second_pass = starts.size() > 1 && earliest < 0.0;
  if (*second_pass) starts = split(az[0] + dir * (earliest - 1e-6));
  const int rings = static_cast<int>(starts.size());
  std::vector<int> ring(p.size());
  std::vector<double> elevation(rings, 0.0), count(rings, 0.0);
  for (int r = 0, i = 0; r < rings; ++r) {
    for (; i < static_cast<int>(r + 1 < rings ? starts[r + 1] : p.size()); ++i) {
      ring[i] = r;
      elevation[r] += FastAtan2(p[i].z(), p[i].head<2>().norm());
      ++count[r];
    }
  }
  if (rings > 1 && elevation[0] / count[0] > elevation[rings - 1] / count[rings - 1])
    for (int& r : ring) r = rings - 1 - r;  // ring 0 is the lowest beam
  return ring;
}

// A firing-order scan that makes the split's decisions close: rings of 5-300 points (some below
// min_points_per_ring) in either direction from a random seam, their starts jittered around it,
// backward jitter, single points thrown back by 1.5 rad (with a threshold below that, rings start
// behind the seam: the second pass), repeated azimuths (dual returns), gaps, points on the line of
// the seam (exactly at the seam's azimuth and +-1e-9 rad around it and its opposite), NaN points
// and points on the axis.
std::vector<Eigen::Vector3d> CloseCallScan(std::mt19937* rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double seam = M_PI * (2 * unit(*rng) - 1), dir = unit(*rng) < 0.5 ? 1.0 : -1.0;
  const int rings = 2 + static_cast<int>(unit(*rng) * 12);
  std::vector<Eigen::Vector3d> p;
  auto add = [&](double azimuth, double elevation) {
    const double range = 2.0 + 40.0 * unit(*rng);
    p.emplace_back(range * std::cos(elevation) * std::cos(azimuth),
                   range * std::cos(elevation) * std::sin(azimuth), range * std::sin(elevation));
  };
  for (int r = 0; r < rings; ++r) {
    const int m = unit(*rng) < 0.1 ? 5 + static_cast<int>(unit(*rng) * 15)
                                   : 20 + static_cast<int>(unit(*rng) * 280);
    const double start = seam + (r > 0 ? 0.02 * (unit(*rng) - 0.5) : 0.0);
    const double elevation = -0.4 + 0.05 * r;
    for (int j = 0; j < m; ++j) {
      double a = start + dir * 2 * M_PI * (j + 0.3 * (unit(*rng) - 0.5)) / m;
      const double kind = unit(*rng);
      if (kind < 0.03) {
        a = seam + dir * 1e-9 * (unit(*rng) < 0.5 ? -1 : 1);
      } else if (kind < 0.05) {
        a = seam;
      } else if (kind < 0.07) {
        a = seam + M_PI + 1e-9 * (unit(*rng) < 0.5 ? -1 : 1);
      } else if (kind < 0.08) {
        continue;  // a gap
      } else if (kind < 0.09) {
        a -= dir * 1.5;
      }
      add(a, elevation);
      if (kind > 0.97) p.push_back(p.back());  // a repeated azimuth
      if (kind > 0.995) p.emplace_back(std::nan(""), 1.0, 0.0);
      if (kind > 0.993 && kind <= 0.995) p.emplace_back(0.0, 0.0, 1.0);
    }
  }
  return p;
}

TEST(LidarModel, ScanOrderRingsMatchTheAzimuthDefinition) {
  std::mt19937 rng(20261201);
  constexpr int kScans = 1000;
  const std::vector<std::pair<double, int>> settings = {
      {ScanOrderOptions().wrap_threshold_rad, 16}, {2.0, 16}, {1.0, 16}, {1.0, 1}};
  for (const auto& [threshold, min_points] : settings) {
    ScanOrderOptions options;
    options.wrap_threshold_rad = threshold;
    options.min_points_per_ring = min_points;
    int second_pass = 0, clockwise = 0, several = 0;
    for (int trial = 0; trial < kScans; ++trial) {
      LidarScan scan;
      scan.points = CloseCallScan(&rng);
      bool second = false;
      double dir = 0.0;
      const std::vector<int> expected = ReferenceRings(scan.points, options, &second, &dir);
      const RingAssignmentStats stats = AssignRingsFromScanOrder(&scan, options);
      ASSERT_EQ(scan.ring, expected) << "threshold " << threshold << ", scan " << trial;
      second_pass += second;
      clockwise += dir < 0.0;
      several += stats.rings_found > 1;
    }
    // Both directions, several rings and (below the default threshold) the second pass were met.
    std::printf(
        "threshold %.2f, min points %d: %d scans, %d clockwise, %d with several rings, %d "
        "took the second pass\n",
        threshold, min_points, kScans, clockwise, several, second_pass);
    EXPECT_GT(clockwise, kScans / 3);
    EXPECT_LT(clockwise, kScans * 2 / 3);
    EXPECT_GT(several, kScans * 9 / 10);
    if (threshold < 3.0) {
      EXPECT_GT(second_pass, kScans / 10);
    }
  }
}

// The direction that the first 4096 steps take is not that of the scan: a slow drift backwards
// over them, then ten rings forwards.
TEST(LidarModel, ScanOrderRingsWhenTheFirstStepsRunBackwards) {
  LidarScan scan;
  for (int i = 0; i < 4200; ++i)
    scan.points.emplace_back(10 * std::cos(-1e-5 * i), 10 * std::sin(-1e-5 * i), -1.0);
  for (int i = 0; i < 10000; ++i)
    scan.points.emplace_back(10 * std::cos(2 * M_PI * i / 1000), 10 * std::sin(2 * M_PI * i / 1000),
                             i / 1000);
  bool second = false;
  double dir = 0.0;
  const std::vector<int> expected = ReferenceRings(scan.points, {}, &second, &dir);
  EXPECT_EQ(dir, 1.0);
  EXPECT_EQ(AssignRingsFromScanOrder(&scan).rings_found, 11);  // the drift, then the ten rings
  EXPECT_EQ(scan.ring, expected);
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

// Every scan of the KITTI extract: the same rings as the definition from every azimuth.
TEST(LidarModel, ScanOrderRingsMatchTheAzimuthDefinitionOnRealScans) {
  const fs::path dir =
      fs::path(PLUCKER_SHARED_DATA_DIR) / "kitti-odometry-00/sequences/00/velodyne";
  if (!fs::exists(dir / "000000.bin")) GTEST_SKIP() << "no KITTI extract at " << dir;
  int scans = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".bin") continue;
    LidarScan scan = io::ReadKittiBin(entry.path().string());
    bool second = false;
    double dir_sign = 0.0;
    const std::vector<int> expected = ReferenceRings(scan.points, {}, &second, &dir_sign);
    EXPECT_GE(AssignRingsFromScanOrder(&scan).rings_found, 62) << entry.path();
    EXPECT_EQ(scan.ring, expected) << entry.path();
    ++scans;
  }
  EXPECT_EQ(scans, 16);
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
