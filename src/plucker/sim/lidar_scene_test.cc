#include "plucker/sim/lidar_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "plucker/sim/lidar_sim.h"

namespace plucker {
namespace sim {
namespace {

TEST(RayIntersection, RectangleAtAnalyticDistance) {
  Rectangle r;
  r.center = Eigen::Vector3d(10, 0, 2);
  r.u = Eigen::Vector3d::UnitY();
  r.v = Eigen::Vector3d::UnitZ();
  r.half_u = 3;
  r.half_v = 2;
  const Eigen::Vector3d o(0, 1, 1.5);
  const Eigen::Vector3d d = Eigen::Vector3d(1, 0.1, 0.05).normalized();
  const auto hit = IntersectRectangle(r, o, d, 0.0, 100.0);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->distance, 10.0 / d.x(), 1e-12);
  EXPECT_NEAR(hit->normal.x(), -1.0, 1e-12);            // faces the origin
  EXPECT_FALSE(IntersectRectangle(r, o, d, 0.0, 5.0));  // beyond t_max
  EXPECT_FALSE(
      IntersectRectangle(r, o, Eigen::Vector3d(1, 0.5, 0).normalized(), 0, 100));  // beside
  EXPECT_FALSE(IntersectRectangle(r, o, Eigen::Vector3d::UnitY(), 0, 100));        // parallel
  EXPECT_FALSE(IntersectRectangle(r, o, -d, 0, 100));                              // behind
}

TEST(RayIntersection, BoxAxisAlignedYawedAndFromInside) {
  Box b;
  b.center = Eigen::Vector3d(20, 0, 1);
  b.half_size = Eigen::Vector3d(2, 3, 1);
  const Eigen::Vector3d o(0, 0, 1);
  auto hit = IntersectBox(b, o, Eigen::Vector3d::UnitX(), 0, 100);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->distance, 18.0, 1e-12);
  EXPECT_NEAR(hit->normal.x(), -1.0, 1e-12);
  // Yawed by 45 deg: the near vertical edge points at the origin, at 20 - 2*sqrt(2) along x if
  // the box is square in xy.
  b.half_size = Eigen::Vector3d(2, 2, 1);
  b.yaw = M_PI / 4;
  hit = IntersectBox(b, o, Eigen::Vector3d::UnitX(), 0, 100);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->distance, 20.0 - 2.0 * std::sqrt(2.0), 1e-9);
  // From inside: the exit face.
  hit = IntersectBox(b, b.center, Eigen::Vector3d::UnitZ(), 0, 100);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->distance, 1.0, 1e-12);
  EXPECT_FALSE(IntersectBox(b, o, Eigen::Vector3d::UnitY(), 0, 100));
}

TEST(RayIntersection, CylinderSideAndCap) {
  Cylinder c;
  c.center = Eigen::Vector2d(10, 0);
  c.radius = 0.5;
  c.z_min = 0;
  c.z_max = 6;
  auto hit = IntersectCylinder(c, Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::UnitX(), 0, 100);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->distance, 9.5, 1e-12);
  EXPECT_NEAR(hit->normal.x(), -1.0, 1e-12);
  // Off-centre ray at lateral offset 0.3: distance 10 - sqrt(0.25 - 0.09).
  hit = IntersectCylinder(c, Eigen::Vector3d(0, 0.3, 1), Eigen::Vector3d::UnitX(), 0, 100);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->distance, 10.0 - std::sqrt(0.16), 1e-12);
  // From above onto the cap.
  hit = IntersectCylinder(c, Eigen::Vector3d(10.1, 0, 9), -Eigen::Vector3d::UnitZ(), 0, 100);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->distance, 3.0, 1e-12);
  EXPECT_NEAR(hit->normal.z(), 1.0, 1e-12);
  // Over the top and beside: misses.
  EXPECT_FALSE(IntersectCylinder(c, Eigen::Vector3d(0, 0, 7), Eigen::Vector3d::UnitX(), 0, 100));
  EXPECT_FALSE(IntersectCylinder(c, Eigen::Vector3d(0, 0.6, 1), Eigen::Vector3d::UnitX(), 0, 100));
}

TEST(LidarScene, GroundPlane) {
  LidarScene scene;
  scene.Build();
  const Eigen::Vector3d d = Eigen::Vector3d(1, 0, -1).normalized();
  const auto hit = scene.Cast(Eigen::Vector3d(0, 0, 2), d, 0.1, 100);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->distance, 2.0 * std::sqrt(2.0), 1e-12);
  EXPECT_FALSE(scene.Cast(Eigen::Vector3d(0, 0, 2), Eigen::Vector3d::UnitX(), 0.1, 100));
}

// The grid must return exactly what testing every primitive returns.
TEST(LidarScene, GridMatchesBruteForce) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-60, 60), h(0.2, 10), a(-M_PI, M_PI);
  LidarScene grid(0.0, 4.0), brute(0.0, 1e6);
  for (int i = 0; i < 150; ++i) {
    Box b;
    b.center = Eigen::Vector3d(u(rng), u(rng), h(rng));
    b.half_size = Eigen::Vector3d(h(rng) / 3, h(rng) / 3, h(rng) / 3);
    b.yaw = a(rng);
    Cylinder c;
    c.center = Eigen::Vector2d(u(rng), u(rng));
    c.radius = h(rng) / 20;
    c.z_max = h(rng);
    Rectangle r;
    r.center = Eigen::Vector3d(u(rng), u(rng), h(rng));
    r.u = Eigen::Vector3d(std::cos(a(rng)), std::sin(a(rng)), 0).normalized();
    r.v = Eigen::Vector3d::UnitZ();
    r.half_u = h(rng);
    r.half_v = h(rng) / 2;
    for (LidarScene* s : {&grid, &brute}) {
      s->AddBox(b);
      s->AddCylinder(c);
      s->AddRectangle(r);
    }
  }
  grid.Build();
  brute.Build();
  int hits = 0;
  for (int k = 0; k < 5000; ++k) {
    const Eigen::Vector3d o(u(rng), u(rng), h(rng));
    const Eigen::Vector3d d = Eigen::Vector3d(u(rng), u(rng), u(rng) / 4).normalized();
    const auto g = grid.Cast(o, d, 0.5, 80), b = brute.Cast(o, d, 0.5, 80);
    ASSERT_EQ(g.has_value(), b.has_value()) << k;
    if (g) {
      ++hits;
      EXPECT_NEAR(g->distance, b->distance, 1e-9);
      EXPECT_EQ(g->primitive, b->primitive);
    }
  }
  EXPECT_GT(hits, 1000);
}

TEST(LidarScene, UrbanAndCorridorScenes) {
  const LidarScene urban = MakeUrbanScene();
  EXPECT_GT(urban.num_primitives(), 500u);
  double length = 0;
  for (std::size_t i = 0; i < urban.route.size(); ++i) {
    length += (urban.route[(i + 1) % urban.route.size()] - urban.route[i]).norm();
  }
  EXPECT_GT(length, 1000.0);
  // The route runs along streets: looking up from the route, nothing overhead.
  for (const Eigen::Vector2d& p : urban.route) {
    EXPECT_FALSE(urban.Cast(Eigen::Vector3d(p.x(), p.y(), 1.7), Eigen::Vector3d::UnitZ(), 0, 100));
  }
  const LidarScene corridor = MakeCorridorScene();
  const auto side = corridor.Cast(Eigen::Vector3d(100, 0, 1.7), Eigen::Vector3d::UnitY(), 0, 100);
  ASSERT_TRUE(side.has_value());
  EXPECT_NEAR(side->distance, 3.0, 1e-12);
  const auto up = corridor.Cast(Eigen::Vector3d(100, 0, 1.7), Eigen::Vector3d::UnitZ(), 0, 100);
  ASSERT_TRUE(up.has_value());
  EXPECT_NEAR(up->distance, 2.3, 1e-12);
  EXPECT_THROW(MakeScene("forest", 1), std::invalid_argument);
}

TEST(LidarScene, HighwayIsAnOpenRoadWithRails) {
  const LidarScene highway = MakeScene("highway", 1);
  EXPECT_EQ(highway.name, "highway");
  EXPECT_EQ(highway.route_speed, 30.0);
  VehicleTrajectoryOptions motion;
  motion.speed = highway.route_speed;
  motion.corner_radius = highway.route_corner_radius;
  const VehicleTrajectory drive(highway.route, motion);
  EXPECT_GT(drive.loop_length(), 9000.0);
  EXPECT_NEAR(drive.DistanceAt(0.1), 3.0, 1e-12);  // 3 m per 10 Hz scan
  int rails = 0, samples = 0;
  for (double s = 0.0; s < drive.loop_length(); s += 50.0, ++samples) {
    const SE3d T_w_s = drive.T_w_s(s / motion.speed);
    const Eigen::Matrix3d R = T_w_s.RotationMatrix();
    const Eigen::Vector3d p = T_w_s.translation();
    // The right guard rail's inner face, 4.45 m to the right at rail height (chords of the
    // curves: within 2 cm), and nothing overhead.
    const auto right = highway.Cast(Eigen::Vector3d(p.x(), p.y(), 0.6), -(R.col(1)), 0, 50);
    if (right && std::abs(right->distance - 4.45) < 0.02) ++rails;
    EXPECT_FALSE(highway.Cast(p, Eigen::Vector3d::UnitZ(), 0, 100)) << "s = " << s;
  }
  EXPECT_EQ(rails, samples);
  // Along the first straight, looking ahead at sensor height: open road within 120 m (the
  // along-track direction is fixed by the ground and rails alone, besides sparse objects).
  for (double s = 0.0; s <= 500.0; s += 25.0) {
    const SE3d T_w_s = drive.T_w_s(s / motion.speed);
    EXPECT_FALSE(highway.Cast(T_w_s.translation(), T_w_s.RotationMatrix().col(0), 0, 120))
        << "s = " << s;
  }
  // A scan there: mostly ground, a few percent rails and objects, no hit beyond the range.
  LidarSimOptions sensor;
  for (int k = 0; k < 32; ++k) sensor.elevation_rad.push_back((-24.0 + 0.8 * k) * M_PI / 180);
  sensor.azimuth_steps = 900;
  const LidarSimulator simulator(highway, sensor);
  const LidarScan scan = simulator.Scan(drive, 2.0, 0);
  ASSERT_GT(scan.size(), 10000u);
  std::size_t off_ground = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (scan.points[i].z() > -1.5) ++off_ground;  // sensor frame, 1.73 m above the ground
  }
  EXPECT_GT(off_ground, scan.size() / 50);
  EXPECT_LT(off_ground, scan.size() / 2);
}

}  // namespace
}  // namespace sim
}  // namespace plucker
