// Procedural 3D scenes for LiDAR simulation, made of analytic primitives, and ray casting
// against them with a 2D uniform grid over the ground plane (x, y) as acceleration structure.
//
// World frame w: z up, ground at z = 0. No I/O.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace plucker {
namespace sim {

// A bounded plane: the rectangle center + a*u + b*v, |a| <= half_u, |b| <= half_v; normal u x v.
struct Rectangle {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d u = Eigen::Vector3d::UnitX();  // unit
  Eigen::Vector3d v = Eigen::Vector3d::UnitY();  // unit, orthogonal to u
  double half_u = 1.0, half_v = 1.0;
};

// A box rotated by `yaw` about the vertical axis (yaw = 0: axis-aligned).
struct Box {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d half_size = Eigen::Vector3d::Ones();
  double yaw = 0.0;
};

// A vertical cylinder (pole, tree trunk): axis through (x, y), from z_min to z_max, capped.
struct Cylinder {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double radius = 0.1;
  double z_min = 0.0, z_max = 5.0;
};

struct RayHit {
  double distance = 0.0;                              // along the unit direction
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit, facing the ray origin
  int primitive = -1;                                 // index in LidarScene::primitive order
};

// Ray / primitive intersections: the smallest t in (t_min, t_max] with origin + t*dir on the
// primitive (dir must be unit), or nullopt.
std::optional<RayHit> IntersectRectangle(const Rectangle& r, const Eigen::Vector3d& origin,
                                         const Eigen::Vector3d& dir, double t_min, double t_max);
std::optional<RayHit> IntersectBox(const Box& b, const Eigen::Vector3d& origin,
                                   const Eigen::Vector3d& dir, double t_min, double t_max);
std::optional<RayHit> IntersectCylinder(const Cylinder& c, const Eigen::Vector3d& origin,
                                        const Eigen::Vector3d& dir, double t_min, double t_max);

class LidarScene {
 public:
  // The infinite ground plane z = ground_z is always present (primitive index -2 in hits).
  explicit LidarScene(double ground_z = 0.0, double grid_cell = 8.0);

  int AddRectangle(const Rectangle& r);
  int AddBox(const Box& b);
  int AddCylinder(const Cylinder& c);
  // Builds the acceleration grid; call after the last Add*. Cast() before Build() sees only the
  // ground (Cast stays const and thread-safe; the factories call Build()).
  void Build();

  // First hit along the unit ray within (t_min, t_max], or nullopt. Thread-safe after Build().
  std::optional<RayHit> Cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                             double t_min, double t_max) const;

  std::size_t num_primitives() const { return kinds_.size(); }
  bool has_ground() const { return has_ground_; }
  void set_has_ground(bool g) { has_ground_ = g; }

  // A closed polyline the vehicle drives along (world xy at ground level), set by the scene
  // factories; consecutive points are distinct.
  std::vector<Eigen::Vector2d> route;
  std::string name;
  // How the scene is driven by default (VehicleTrajectoryOptions speed and corner_radius).
  double route_speed = 10.0;          // m/s
  double route_corner_radius = 12.0;  // m

 private:
  enum class Kind : std::uint8_t { kRectangle, kBox, kCylinder };
  void AddToGrid(int id, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi);
  std::optional<RayHit> IntersectPrimitive(int id, const Eigen::Vector3d& origin,
                                           const Eigen::Vector3d& dir, double t_min,
                                           double t_max) const;
  void Bounds(int id, Eigen::Vector2d* lo, Eigen::Vector2d* hi) const;

  double ground_z_;
  double cell_;
  bool has_ground_ = true;
  bool built_ = false;
  std::vector<Kind> kinds_;
  std::vector<int> index_;  // into the per-kind arrays
  std::vector<Rectangle> rectangles_;
  std::vector<Box> boxes_;
  std::vector<Eigen::Vector2d> box_cos_sin_;  // cos(yaw), sin(yaw) of each box
  std::vector<Cylinder> cylinders_;
  // Grid: cells_[cy * nx_ + cx] lists primitive ids overlapping the cell (CSR layout).
  Eigen::Vector2d grid_min_ = Eigen::Vector2d::Zero();
  int nx_ = 0, ny_ = 0;
  std::vector<int> cell_start_, cell_items_;
  std::vector<int> unbounded_;  // primitives too large for the grid (tested for every ray)
};

struct UrbanSceneOptions {
  int blocks_x = 3, blocks_y = 3;  // city blocks; the route circles the whole grid
  double block_size = 90.0;        // metres, building block edge
  double street_width = 16.0;      // metres between facades
  double pole_spacing = 25.0;      // metres along the kerb
  double car_spacing = 15.0;       // metres (some slots empty, seeded)
  std::uint64_t seed = 1;
};
// Ground plane, building facades with corners and window recesses, poles, parked cars and a
// street grid; the route follows the streets around the block grid with turns at intersections
// (loop length 4 * blocks * (block + street) = about 1.3 km with the defaults).
LidarScene MakeUrbanScene(const UrbanSceneOptions& options = UrbanSceneOptions());

struct CorridorSceneOptions {
  double length = 1000.0;  // metres, straight along x
  double width = 6.0;
  double height = 4.0;
  std::uint64_t seed = 1;
};
// A long featureless rectangular tunnel (floor, two walls, ceiling) with closed ends: LOAM is
// degenerate along its axis. The route runs along the axis and back.
LidarScene MakeCorridorScene(const CorridorSceneOptions& options = CorridorSceneOptions());

struct HighwaySceneOptions {
  double corner_radius = 500.0;     // m, the loop's curves (clamped to fit the legs)
  double speed = 30.0;              // m/s, the scene's default driving speed
  double rail_post_spacing = 4.0;   // m, guard rail posts (0: a bare rail)
  double pole_spacing = 70.0;       // m, mean spacing of the median's lamp poles (+-40 %)
  double sign_spacing = 600.0;      // m, mean spacing of the gantry-less roadside signs
  double plant_spacing = 8.0;       // m, mean spacing of trees and bushes per verge (0: none)
  double building_spacing = 900.0;  // m, mean spacing of the few buildings (30-90 m off)
  std::uint64_t seed = 1;
};
// An open road: a 9.0 km loop of long straights (one with a gentle S bend) and wide curves, the
// vehicle in the right lane of a dual carriageway; guard rails on the right shoulder, the median
// and the far side (the same cross-section everywhere: only the rail posts, sparse poles, trees
// and bushes on the verges, signs and a few buildings fix the along-road position), a flat
// ground, nothing overhead.
// Driven at 30 m/s by default (3 m per 10 Hz scan).
LidarScene MakeHighwayScene(const HighwaySceneOptions& options = HighwaySceneOptions());

// "urban" | "corridor" | "highway"; throws std::invalid_argument otherwise.
LidarScene MakeScene(const std::string& name, std::uint64_t seed);

}  // namespace sim
}  // namespace plucker
