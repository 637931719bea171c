// Test helpers (header-only, not installed): a tiny ray caster of axis-aligned boxes that makes
// ring-ordered spinning-LiDAR scans, so the lidar tests build their synthetic data themselves.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "plucker/geometry/se3.h"
#include "plucker/sensor/lidar_scan.h"

namespace plucker {
namespace lidar {
namespace test {

struct Box {
  Eigen::Vector3d lo, hi;
  bool inside = false;  // the sensor sees it from the inside (a room / corridor)
};

struct Scene {
  std::vector<Box> boxes;

  // Distance along the unit ray (origin o, direction d) to the first surface, or +inf.
  double Cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d) const {
    double best = std::numeric_limits<double>::infinity();
    for (const Box& b : boxes) {
      double t_near = -std::numeric_limits<double>::infinity();
      double t_far = std::numeric_limits<double>::infinity();
      bool miss = false;
      for (int a = 0; a < 3; ++a) {
        if (std::abs(d(a)) < 1e-12) {
          if (o(a) < b.lo(a) || o(a) > b.hi(a)) miss = true;
          continue;
        }
        double t1 = (b.lo(a) - o(a)) / d(a), t2 = (b.hi(a) - o(a)) / d(a);
        if (t1 > t2) std::swap(t1, t2);
        t_near = std::max(t_near, t1);
        t_far = std::min(t_far, t2);
      }
      if (miss || t_near > t_far) continue;
      const double t = b.inside ? t_far : t_near;
      if (t > 1e-6 && t < best) best = t;
    }
    return best;
  }
};

// An urban-like scene: a large walled area with ground and many box buildings / pillars.
inline Scene UrbanScene() {
  Scene s;
  s.boxes.push_back({Eigen::Vector3d(-80, -40, -1.8), Eigen::Vector3d(80, 40, 30), true});
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 40; ++i) {
    const double x = -70 + 140 * u(rng), y = (i % 2 ? 1 : -1) * (8 + 25 * u(rng));
    const double w = 1 + 6 * u(rng), h = 2 + 10 * u(rng);
    s.boxes.push_back({Eigen::Vector3d(x, y, -1.8), Eigen::Vector3d(x + w, y + w * 0.7, h)});
  }
  for (int i = 0; i < 20; ++i) {  // thin poles near the road
    const double x = -70 + 140 * u(rng), y = (i % 2 ? 1 : -1) * (5 + 2 * u(rng));
    s.boxes.push_back({Eigen::Vector3d(x, y, -1.8), Eigen::Vector3d(x + 0.3, y + 0.3, 4)});
  }
  return s;
}

// A long featureless corridor along x (walls, floor, ceiling all parallel to x).
inline Scene CorridorScene() {
  Scene s;
  s.boxes.push_back({Eigen::Vector3d(-500, -2, -1.5), Eigen::Vector3d(500, 2, 2.5), true});
  return s;
}

struct ScanPattern {
  int rings = 32;
  double min_elevation_deg = -25, max_elevation_deg = 10;
  int azimuth_steps = 1000;
  double max_range = 100;
  double noise = 0.0;  // metres, Gaussian along the ray
};

// A scan from sensor pose T_w_s, points ring by ring (ring 0 lowest), each ring one revolution in
// firing order, ring field filled.
inline LidarScan MakeScan(const Scene& scene, const SE3d& T_w_s, const ScanPattern& pattern,
                          unsigned seed = 1) {
  LidarScan scan;
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, pattern.noise > 0 ? pattern.noise : 1.0);
  const Eigen::Matrix3d R = T_w_s.RotationMatrix();
  for (int r = 0; r < pattern.rings; ++r) {
    const double el =
        (pattern.min_elevation_deg + (pattern.max_elevation_deg - pattern.min_elevation_deg) * r /
                                         std::max(1, pattern.rings - 1)) *
        M_PI / 180.0;
    for (int a = 0; a < pattern.azimuth_steps; ++a) {
      const double az = M_PI - 2.0 * M_PI * a / pattern.azimuth_steps;  // clockwise from -x
      const Eigen::Vector3d d_s(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                                std::sin(el));
      double range = scene.Cast(T_w_s.translation(), R * d_s);
      if (!(range < pattern.max_range)) continue;
      if (pattern.noise > 0) range += pattern.noise * noise(rng);
      scan.points.push_back(range * d_s);
      scan.ring.push_back(r);
    }
  }
  return scan;
}

}  // namespace test
}  // namespace lidar
}  // namespace plucker
