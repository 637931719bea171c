#include "plucker/lidar/voxel_map.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <stdexcept>

namespace plucker {
namespace lidar {
namespace {

// KNearest(q, k, max_d) against brute force over `pts`: the count, the distances in order and the
// reach bound (the nearest point not returned). Returns the count found.
int CheckKNearest(const VoxelMap& map, const std::vector<Eigen::Vector3d>& pts,
                  const Eigen::Vector3d& q, int k, double max_d) {
  std::vector<Eigen::Vector3d> nn;
  float reach = -1.0f;
  const int found = map.KNearest(q, k, max_d, &nn, &reach);
  std::vector<double> d;
  for (const auto& p : pts) d.push_back((p - q).norm());
  std::sort(d.begin(), d.end());
  const int within = static_cast<int>(std::upper_bound(d.begin(), d.end(), max_d) - d.begin());
  EXPECT_EQ(found, std::min(k, within)) << q.transpose();
  for (int n = 0; n < std::min(found, within); ++n) EXPECT_NEAR((nn[n] - q).norm(), d[n], 1e-5);
  if (found < static_cast<int>(d.size())) {
    EXPECT_GE(d[found], reach - 1e-5) << q.transpose();
  }
  return found;
}

TEST(VoxelMapTest, KNearestMatchesBruteForce) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-5, 5);
  VoxelMap map({1.0, 1000, 0.0, 1e9});
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 5000; ++i) pts.emplace_back(u(rng), u(rng), u(rng));
  ASSERT_EQ(map.AddPoints(pts), 5000);
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    checked += CheckKNearest(map, pts, Eigen::Vector3d(u(rng), u(rng), u(rng)), 5, 1.0);
    ASSERT_FALSE(::testing::Test::HasFailure()) << "trial " << trial;
  }
  EXPECT_GT(checked, 200 * 4);  // nearly every query finds its 5 neighbours
}

// KNearest's `reach` (what lets the odometry reuse a search in its later rounds) is a lower bound
// of the distance to every point it did not return, for dense and for sparse neighbourhoods
// (fewer than k points within max_distance), and not a vacuous one.
TEST(VoxelMapTest, KNearestReachBoundsEveryPointNotReturned) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-6, 6);
  for (const int num_points : {20000, 300}) {
    VoxelMap map({1.0, 1000, 0.0, 1e9});
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < num_points; ++i) pts.emplace_back(u(rng), u(rng), u(rng));
    ASSERT_EQ(map.AddPoints(pts), num_points);
    std::vector<Eigen::Vector3d> nn;
    int checked = 0, sparse = 0;
    double reach_sum = 0.0;
    for (int trial = 0; trial < 200; ++trial) {
      const Eigen::Vector3d q(u(rng), u(rng), u(rng));
      float reach = -1.0f;
      const int found = map.KNearest(q, 8, 0.8, &nn, &reach);
      sparse += found < 8;
      reach_sum += reach;
      for (const auto& p : pts) {
        const bool returned = std::any_of(
            nn.begin(), nn.end(), [&](const Eigen::Vector3d& n) { return (n - p).norm() < 1e-6; });
        if (returned) continue;
        ASSERT_GE((p - q).norm(), reach - 1e-5) << "trial " << trial;
        ++checked;
      }
      if (found > 0) {
        EXPECT_GE(reach, (nn.back() - q).norm() - 1e-5);
      }
      if (found < 8) {
        EXPECT_GT(reach, 0.8);  // nothing else within max_distance
      }
    }
    EXPECT_GE(checked, 200 * (num_points - 8));  // every point not returned was checked
    EXPECT_GT(reach_sum / 200, 0.2);
    if (num_points == 300) {
      EXPECT_GT(sparse, 150);  // the sparse case was exercised
    }
    if (num_points == 20000) {
      EXPECT_LT(sparse, 20);
    }
  }
}

TEST(VoxelMapTest, SpacingAndCapLimitDensity) {
  VoxelMap map({1.0, 5, 0.2, 1e9});
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 1000; ++i) pts.emplace_back(0.5 + 1e-4 * i, 0.5, 0.5);  // 10 cm of points
  EXPECT_EQ(map.AddPoints(pts), 1);  // all within 0.2 m of the first
  pts.clear();
  for (int i = 0; i < 10; ++i) pts.emplace_back(0.05 + 0.09 * i, 0.05 + 0.09 * i, 0.05);
  map.AddPoints(pts);
  EXPECT_LE(map.NumPoints(), 5u);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(map.AddPoints({Eigen::Vector3d(nan, 0, 0)}), 0);
}

TEST(VoxelMapTest, MemoryStaysFlatAsThePoseMovesFar) {
  VoxelMapOptions options;
  options.max_distance = 50.0;
  VoxelMap map(options);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-40, 40);
  std::size_t peak_after_warmup = 0, peak = 0;
  for (int step = 0; step < 2000; ++step) {
    const Eigen::Vector3d origin(5.0 * step, 0.0, 0.0);  // 10 km
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < 500; ++i)
      pts.push_back(origin + Eigen::Vector3d(u(rng), u(rng), 0.3 * u(rng)));
    map.AddPoints(pts);
    map.RemoveFar(origin);
    if (step == 100) peak_after_warmup = map.NumPoints();
    peak = std::max(peak, map.NumPoints());
    if (step % 500 == 0) {
      for (const auto& p : map.Points()) ASSERT_LT((p - origin).norm(), options.max_distance + 2.0);
    }
  }
  EXPECT_GT(peak_after_warmup, 0u);
  EXPECT_LT(peak, 1.3 * peak_after_warmup);
  EXPECT_LT(map.NumVoxels(), 60000u);
}

// The heap is not churned on a long drive: the slots of removed voxels are reused, so the pool
// stops growing once the kept region is full, however far the pose moves.
TEST(VoxelMapTest, RemovedVoxelSlotsAreReused) {
  VoxelMapOptions options;
  options.max_distance = 30.0;
  VoxelMap map(options);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-25, 25);
  std::size_t slots_at_500 = 0;
  int removals = 0;
  for (int step = 0; step < 1500; ++step) {
    const Eigen::Vector3d origin(2.0 * step, 0.0, 0.0);  // 3 km
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < 300; ++i)
      pts.push_back(origin + Eigen::Vector3d(u(rng), u(rng), 0.2 * u(rng)));
    map.AddPoints(pts);
    const std::size_t before = map.NumVoxels();
    map.RemoveFar(origin);
    removals += before > map.NumVoxels();
    ASSERT_GE(map.NumSlots(), map.NumVoxels());
    if (step == 500) slots_at_500 = map.NumSlots();
  }
  EXPECT_GT(removals, 1400);  // voxels were dropped at (nearly) every step
  ASSERT_GT(slots_at_500, 0u);
  EXPECT_LT(map.NumSlots(), 1.1 * slots_at_500);  // no growth over the last 2 km
  // Contents are still right after many reuses: every stored point is near the last origin.
  const Eigen::Vector3d last(2.0 * 1499, 0.0, 0.0);
  for (const auto& p : map.Points()) ASSERT_LT((p - last).norm(), options.max_distance + 2.0);
}

TEST(VoxelMapTest, ClearThenRefill) {
  VoxelMap map({0.5, 10, 0.0, 1e9});
  for (int round = 0; round < 3; ++round) {
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < 100; ++i) pts.emplace_back(0.1 * i + round, 0.0, 0.0);
    EXPECT_EQ(map.AddPoints(pts), 100);
    EXPECT_EQ(map.NumPoints(), 100u);
    std::vector<Eigen::Vector3d> nn;
    ASSERT_EQ(map.KNearest(Eigen::Vector3d(round + 0.31, 0, 0), 1, 0.5, &nn), 1);
    EXPECT_NEAR(nn[0].x(), round + 0.3, 1e-6);
    map.Clear();
    EXPECT_TRUE(map.empty());
    EXPECT_EQ(map.NumVoxels(), 0u);
  }
}

// Queries on the corners of 4x4x4-voxel blocks (where the hash groups voxels) at negative and
// positive coordinates, after RemoveFar emptied a region and the same voxels were refilled from
// the freed slots: KNearest still matches brute force and the pool did not grow.
TEST(VoxelMapTest, KNearestAtBlockCornersAfterRemovalAndRefill) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-6, 6);
  VoxelMap map({0.5, 1000, 0.0, 6.0});
  std::vector<Eigen::Vector3d> pts, removed;
  for (int i = 0; i < 12000; ++i) pts.emplace_back(u(rng), u(rng), u(rng));
  ASSERT_EQ(map.AddPoints(pts), 12000);
  const std::size_t voxels = map.NumVoxels(), slots = map.NumSlots();
  const Eigen::Vector3d origin(-4.0, -4.0, -4.0);
  for (const auto& p : pts) {
    const Eigen::Vector3d centre = ((p / 0.5).array().floor() + 0.5) * 0.5;
    if ((centre - origin).norm() > 6.0) removed.push_back(p);
  }
  map.RemoveFar(origin);
  ASSERT_GT(removed.size(), 4000u);
  EXPECT_EQ(map.NumPoints(), pts.size() - removed.size());
  EXPECT_LT(map.NumVoxels(), voxels);
  ASSERT_EQ(map.AddPoints(removed), static_cast<int>(removed.size()));
  EXPECT_EQ(map.NumVoxels(), voxels);
  EXPECT_EQ(map.NumSlots(), slots);  // the refilled voxels took the freed slots
  EXPECT_EQ(map.Points().size(), pts.size());
  int checked = 0;
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j)
      for (int s = 0; s < 8; ++s) {  // the 8 voxels around the corner (2 i, 2 j, -2 j) m
        const Eigen::Vector3d q(2.0 * i + (s & 1 ? 1e-3 : -1e-3), 2.0 * j + (s & 2 ? 1e-3 : -1e-3),
                                -2.0 * j + (s & 4 ? 1e-3 : -1e-3));
        checked += CheckKNearest(map, pts, q, 6, 0.5);
        ASSERT_FALSE(::testing::Test::HasFailure());
      }
  EXPECT_GT(checked, 7 * 7 * 8 * 2);  // on average more than 2 neighbours per query
}

// KNearest forms a neighbour's key by adding PackedOffset to the query voxel's key: no carry or
// borrow between the axes at the ends of the packable range (+-1048000 voxels, both signs per
// axis), checked on the keys and through KNearest: each of the 26 neighbours holds one point
// 0.125 |offset| from a query near that face, edge or corner of the query's voxel (exact floats).
TEST(VoxelMapTest, KNearestAcrossEveryNeighbourAtTheEndsOfThePackableRange) {
  int keys = 0;
  for (const int end : {1048000, -1048000, 1047999, -1047999, 0})
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const Eigen::Vector3i v(end, -end, end), d(dx, dy, dz);
          ASSERT_EQ(PackVoxel(v + d), PackVoxel(v) + PackedOffset(dx, dy, dz)) << v.transpose();
          ASSERT_EQ(UnpackVoxel(PackVoxel(v) + PackedOffset(dx, dy, dz)), v + d);
          ++keys;
        }
  EXPECT_EQ(keys, 5 * 27);
  int checked = 0;
  for (const double end : {1047999.5, -1047999.5}) {
    const Eigen::Vector3d centre(end, -end, end);  // of the query's voxel (1 m voxels)
    VoxelMap map({1.0, 10, 0.0, 1e12});
    std::vector<Eigen::Vector3d> points;
    std::vector<Eigen::Vector3d> offsets;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
          if (dx || dy || dz) offsets.emplace_back(dx, dy, dz);
    for (const auto& o : offsets) points.push_back(centre + 0.5625 * o);
    ASSERT_EQ(map.AddPoints(points), 26);
    std::vector<Eigen::Vector3d> nn;
    for (std::size_t i = 0; i < offsets.size(); ++i) {
      ASSERT_EQ(map.KNearest(centre + 0.4375 * offsets[i], 1, 1.0, &nn), 1)
          << offsets[i].transpose();
      EXPECT_EQ(nn[0], points[i]) << offsets[i].transpose();
      ++checked;
    }
  }
  EXPECT_EQ(checked, 52);
}

// KNearest looks up only the neighbours in a voxel's mask: the masks follow voxels made before or
// after their neighbours, removed by RemoveFar (their bits left set in the neighbours' masks),
// made again in freed slots and dropped by Clear. A sparse map (most neighbours absent) on a
// moving window, after every step, against brute force over the map's points, with the reach
// bound (which absent neighbours no longer lower) checked as well.
TEST(VoxelMapTest, KNearestAfterVoxelsComeAndGoInAnyOrder) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-3, 3);
  VoxelMap map({0.5, 4, 0.0, 2.5});
  int checked = 0, empty = 0;
  for (int step = 0; step < 60; ++step) {
    const Eigen::Vector3d origin(0.3 * (step % 20), -0.2 * (step % 20), 0.0);
    if (step == 40) map.Clear();
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < 150; ++i) pts.push_back(origin + Eigen::Vector3d(u(rng), u(rng), u(rng)));
    map.AddPoints(pts);
    if (step % 3 == 2) map.RemoveFar(origin);
    const std::vector<Eigen::Vector3d> stored = map.Points();
    for (int trial = 0; trial < 30; ++trial) {
      const Eigen::Vector3d q = origin + 0.5 * Eigen::Vector3d(u(rng), u(rng), u(rng));
      const int found = CheckKNearest(map, stored, q, 3, 0.5);
      ASSERT_FALSE(::testing::Test::HasFailure()) << "step " << step;
      checked += found;
      empty += found == 0;
    }
  }
  EXPECT_GT(checked, 60 * 30);  // more than one neighbour per query on average
  EXPECT_GT(empty, 60);         // and queries with no point near them
}

TEST(VoxelMapTest, RejectsInvalidOptions) {
  EXPECT_THROW(VoxelMap({1.0, 0, 0.1, 10.0}), std::invalid_argument);
  EXPECT_THROW(VoxelMap({1.0, 10001, 0.1, 10.0}), std::invalid_argument);
  EXPECT_THROW(VoxelMap({0.0, 10, 0.1, 10.0}), std::invalid_argument);
  EXPECT_NO_THROW(VoxelMap({0.2, 1, 0.0, 1e12}));
}

TEST(VoxelMapTest, FarFromTheOriginAndNegativeCoordinates) {
  VoxelMap map({0.5, 10, 0.0, 1e9});
  const Eigen::Vector3d a(-12345.2, 20000.7, -3.3);
  map.AddPoints({a, a + Eigen::Vector3d(0.3, 0, 0)});
  std::vector<Eigen::Vector3d> nn;
  ASSERT_EQ(map.KNearest(a + Eigen::Vector3d(0.01, 0, 0), 2, 0.5, &nn), 2);
  EXPECT_LT((nn[0] - a).norm(), 0.01);
  map.RemoveFar(Eigen::Vector3d::Zero());
  EXPECT_EQ(map.NumPoints(), 2u);  // max_distance 1e9 keeps them
  map.Clear();
  EXPECT_TRUE(map.empty());
}

}  // namespace
}  // namespace lidar
}  // namespace plucker
