// MakeHighwayScene: an open road for the LiDAR simulator (see lidar_scene.h).
#include <cmath>
#include <random>
#include <stdexcept>

#include "plucker/sim/lidar_scene.h"
#include "plucker/sim/lidar_sim.h"

namespace plucker {
namespace sim {
namespace {

double Uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }
double Uniform(std::mt19937_64& rng, double lo, double hi) { return lo + (hi - lo) * Uniform(rng); }

// A point of the driven line: position and heading (rad) at arc length s.
struct RoadPoint {
  Eigen::Vector2d p;
  Eigen::Vector2d forward, left;
  double heading;
};

RoadPoint RoadAt(const VehicleTrajectory& line, double s) {
  const SE3d T = line.T_w_s(s);  // speed 1 m/s: t = s
  RoadPoint r;
  r.p = T.translation().head<2>();
  const Eigen::Vector3d f = T.rotation() * Eigen::Vector3d::UnitX();
  r.forward = f.head<2>().normalized();
  r.left = Eigen::Vector2d(-r.forward.y(), r.forward.x());
  r.heading = std::atan2(r.forward.y(), r.forward.x());
  return r;
}

// Cross-section, lateral offsets from the driven line (+ = left), metres.
constexpr double kRightRail = -4.5;  // right shoulder
constexpr double kMedianRail = 8.0;  // between the carriageways
constexpr double kFarRail = 20.5;    // far side of the opposite carriageway
constexpr double kRailZ = 0.62, kRailHalfHeight = 0.16, kRailHalfThickness = 0.05;
constexpr double kRailPiece = 8.0;  // m, rails are straight boxes of this length along the line

void AddRailPiece(LidarScene* scene, const RoadPoint& a, const RoadPoint& b, double offset) {
  const Eigen::Vector2d pa = a.p + offset * a.left, pb = b.p + offset * b.left;
  const Eigen::Vector2d mid = 0.5 * (pa + pb), d = pb - pa;
  Box rail;
  rail.center = Eigen::Vector3d(mid.x(), mid.y(), kRailZ);
  rail.half_size = Eigen::Vector3d(0.5 * d.norm() + 0.02, kRailHalfThickness, kRailHalfHeight);
  rail.yaw = std::atan2(d.y(), d.x());
  scene->AddBox(rail);
}

void AddPost(LidarScene* scene, const RoadPoint& r, double offset) {
  const Eigen::Vector2d c = r.p + offset * r.left;
  Box post;
  post.center = Eigen::Vector3d(c.x(), c.y(), 0.5 * kRailZ);
  post.half_size = Eigen::Vector3d(0.075, 0.075, 0.5 * kRailZ);
  post.yaw = r.heading;
  scene->AddBox(post);
}

// A roadside sign: a board facing the traffic on two legs, right of the shoulder.
void AddSign(LidarScene* scene, const RoadPoint& r, std::mt19937_64& rng) {
  const double offset = kRightRail - Uniform(rng, 2.0, 4.0);
  const double half_w = Uniform(rng, 1.5, 2.5), z0 = Uniform(rng, 2.5, 4.0), h = 2.5;
  const Eigen::Vector2d c = r.p + offset * r.left;
  Rectangle board;
  board.center = Eigen::Vector3d(c.x(), c.y(), z0 + 0.5 * h);
  board.u = Eigen::Vector3d(r.left.x(), r.left.y(), 0.0);
  board.v = Eigen::Vector3d::UnitZ();
  board.half_u = half_w;
  board.half_v = 0.5 * h;
  scene->AddRectangle(board);
  for (double side : {-1.0, 1.0}) {
    Cylinder leg;
    leg.center = c + side * (half_w - 0.3) * r.left + 0.1 * r.forward;
    leg.radius = 0.08;
    leg.z_max = z0 + 0.5 * h;
    scene->AddCylinder(leg);
  }
}

// Roadside vegetation beyond the rails: a tree (trunk and a box crown) or a bush (a low box).
void AddPlant(LidarScene* scene, const RoadPoint& r, double offset, std::mt19937_64& rng) {
  const Eigen::Vector2d c = r.p + offset * r.left;
  if (Uniform(rng) < 0.5) {
    Cylinder trunk;
    trunk.center = c;
    trunk.radius = Uniform(rng, 0.12, 0.3);
    trunk.z_max = Uniform(rng, 2.0, 3.5);
    scene->AddCylinder(trunk);
    Box crown;
    const double h = Uniform(rng, 2.5, 6.0), w = Uniform(rng, 1.5, 3.0);
    crown.center = Eigen::Vector3d(c.x(), c.y(), trunk.z_max + 0.5 * h);
    crown.half_size = Eigen::Vector3d(w, w, 0.5 * h);
    crown.yaw = Uniform(rng, 0.0, 1.5);
    scene->AddBox(crown);
  } else {
    Box bush;
    const double h = Uniform(rng, 0.6, 1.8);
    bush.center = Eigen::Vector3d(c.x(), c.y(), 0.5 * h);
    bush.half_size = Eigen::Vector3d(Uniform(rng, 0.5, 2.0), Uniform(rng, 0.5, 1.5), 0.5 * h);
    bush.yaw = r.heading + Uniform(rng, -0.5, 0.5);
    scene->AddBox(bush);
  }
}

void AddBuilding(LidarScene* scene, const RoadPoint& r, std::mt19937_64& rng) {
  const double side = Uniform(rng) < 0.5 ? -1.0 : 1.0;
  const double depth = Uniform(rng, 10.0, 30.0);
  const double gap = Uniform(rng, 30.0, 90.0);
  const double offset = side > 0 ? kFarRail + gap + 0.5 * depth : kRightRail - gap - 0.5 * depth;
  const Eigen::Vector2d c = r.p + offset * r.left;
  Box b;
  const double height = Uniform(rng, 5.0, 14.0);
  b.center = Eigen::Vector3d(c.x(), c.y(), 0.5 * height);
  b.half_size = Eigen::Vector3d(0.5 * Uniform(rng, 15.0, 50.0), 0.5 * depth, 0.5 * height);
  b.yaw = r.heading + Uniform(rng, -0.3, 0.3);
  scene->AddBox(b);
}

}  // namespace

LidarScene MakeHighwayScene(const HighwaySceneOptions& opt) {
  if (!(opt.corner_radius >= 50) || !(opt.speed > 0) || !(opt.rail_post_spacing >= 0) ||
      !(opt.pole_spacing > 5) || !(opt.plant_spacing >= 0) || !(opt.sign_spacing > 20) ||
      !(opt.building_spacing > 50)) {
    throw std::invalid_argument("MakeHighwayScene: invalid options");
  }
  std::mt19937_64 rng(opt.seed * 0x9E3779B97F4A7C15ull + 29);
  LidarScene scene(0.0, 8.0);
  scene.name = "highway";
  scene.route_speed = opt.speed;
  scene.route_corner_radius = opt.corner_radius;
  // The loop starts on the first long straight (collinear with the previous point: no arc at
  // s = 0), then a gentle S bend (+-5 deg), then wide curves.
  scene.route = {{-700, 0}, {0, 0}, {900, -80}, {1800, 0}, {1800, 1600}, {-1500, 1600}, {-1500, 0}};
  VehicleTrajectoryOptions unit;
  unit.speed = 1.0;
  unit.corner_radius = opt.corner_radius;
  unit.mount_height = 0.0;
  const VehicleTrajectory line(scene.route, unit);
  const double length = line.loop_length();
  const int pieces = static_cast<int>(std::ceil(length / kRailPiece));
  for (int k = 0; k < pieces; ++k) {
    const RoadPoint a = RoadAt(line, k * length / pieces);
    const RoadPoint b = RoadAt(line, (k + 1) * length / pieces);
    for (double offset : {kRightRail, kMedianRail, kFarRail}) AddRailPiece(&scene, a, b, offset);
  }
  if (opt.rail_post_spacing > 0) {
    const int posts = static_cast<int>(length / opt.rail_post_spacing);
    for (int k = 0; k < posts; ++k) {
      const RoadPoint r = RoadAt(line, k * length / posts);
      AddPost(&scene, r, kRightRail - 0.15);
      AddPost(&scene, r, kMedianRail + 0.15);
    }
  }
  auto next = [&](double s, double spacing) { return s + spacing * Uniform(rng, 0.6, 1.4); };
  for (double s = next(0.0, opt.pole_spacing); s < length; s = next(s, opt.pole_spacing)) {
    const RoadPoint r = RoadAt(line, s);
    Cylinder pole;
    pole.center = r.p + (kMedianRail + 0.4) * r.left;
    pole.radius = Uniform(rng, 0.1, 0.16);
    pole.z_max = Uniform(rng, 9.0, 12.0);
    scene.AddCylinder(pole);
  }
  if (opt.plant_spacing > 0) {  // both verges, 2-12 m beyond the outer rails
    for (double side : {-1.0, 1.0}) {
      for (double s = next(0.0, opt.plant_spacing); s < length; s = next(s, opt.plant_spacing)) {
        const double gap = Uniform(rng, 2.0, 12.0);
        AddPlant(&scene, RoadAt(line, s), side > 0 ? kFarRail + gap : kRightRail - gap, rng);
      }
    }
  }
  for (double s = next(0.0, opt.sign_spacing); s < length; s = next(s, opt.sign_spacing)) {
    AddSign(&scene, RoadAt(line, s), rng);
  }
  for (double s = next(0.0, opt.building_spacing); s < length; s = next(s, opt.building_spacing)) {
    AddBuilding(&scene, RoadAt(line, s), rng);
  }
  scene.Build();
  return scene;
}

}  // namespace sim
}  // namespace plucker
