#include "plucker/sim/scene.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace plucker {
namespace sim {

using Eigen::Vector3d;

std::string SceneKindName(SceneKind kind) {
  switch (kind) {
    case SceneKind::kRoom:
      return "room";
    case SceneKind::kCorridor:
      return "corridor";
    case SceneKind::kFacades:
      return "facades";
  }
  return "room";
}

SceneKind ParseSceneKind(const std::string& name) {
  if (name == "room") return SceneKind::kRoom;
  if (name == "corridor") return SceneKind::kCorridor;
  if (name == "facades") return SceneKind::kFacades;
  throw std::invalid_argument("unknown scene kind '" + name + "' (room, corridor, facades)");
}

namespace {

// A bounded planar patch origin + a u + b v, (a, b) in [0, 1]^2, on planes_w[plane_id].
struct Patch {
  Vector3d origin, u, v;
  int plane_id;
};

// A vertical wall seen from the free space: bottom corner `origin`, unit horizontal direction
// `dir`, `length` along it, unit normal `n` into the free space.
struct Wall {
  Vector3d origin, dir;
  double length;
  Vector3d n;
  int plane_id;
};

class SceneBuilder {
 public:
  SceneBuilder(Scene* scene, double frame_depth, std::mt19937_64* rng)
      : scene_(scene), frame_depth_(frame_depth), rng_(rng) {}

  int UniformInt(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(*rng_); }
  double Uniform(double lo, double hi) {
    if (!(hi > lo)) return lo;
    return std::uniform_real_distribution<double>(lo, hi)(*rng_);
  }

  // The plane through p with normal m (towards the free space).
  int AddPlane(const Vector3d& m, const Vector3d& p) {
    const Vector3d m_unit = m.normalized();
    scene_->planes_w.emplace_back(m_unit.x(), m_unit.y(), m_unit.z(), -m_unit.dot(p));
    return static_cast<int>(scene_->planes_w.size()) - 1;
  }
  void AddPatch(const Vector3d& origin, const Vector3d& u, const Vector3d& v, int plane_id) {
    patches_.push_back({origin, u, v, plane_id});
  }
  void AddSegment(const Vector3d& a, const Vector3d& b) {
    if ((b - a).norm() > 1e-6) scene_->segments_w.push_back({a, b});
  }
  void AddOutline(const Vector3d& o, const Vector3d& u, const Vector3d& v) {
    AddSegment(o, o + u);
    AddSegment(o + u, o + u + v);
    AddSegment(o + u + v, o + v);
    AddSegment(o + v, o);
  }
  // An opening o + [0,1] w + [0,1] h in a wall with normal n, framed by a box protruding by
  // frame_depth along n: the outline on the wall, the outline of the frame front and the depth
  // edges joining them. Doors have no bottom edges; windows get a mullion cross on the wall.
  void AddFramedOpening(const Vector3d& o, const Vector3d& w, const Vector3d& h, const Vector3d& n,
                        bool door) {
    const Vector3d f = frame_depth_ * n;
    for (const Vector3d& shift : {Vector3d(Vector3d::Zero()), f}) {
      const Vector3d p = o + shift;
      if (!door) AddSegment(p, p + w);
      AddSegment(p + w, p + w + h);
      AddSegment(p + w + h, p + h);
      AddSegment(p + h, p);
    }
    for (const Vector3d& c : {o, Vector3d(o + w), Vector3d(o + w + h), Vector3d(o + h)}) {
      AddSegment(c, c + f);
    }
    if (!door) {
      AddSegment(o + 0.5 * w, o + 0.5 * w + h);
      AddSegment(o + 0.5 * h, o + 0.5 * h + w);
    }
  }
  void AddWindow(const Wall& wall, double center, double width, double sill, double height) {
    if (width < 0.2 || height < 0.2) return;
    const Vector3d o = wall.origin + (center - 0.5 * width) * wall.dir + sill * Vector3d::UnitZ();
    AddFramedOpening(o, width * wall.dir, height * Vector3d::UnitZ(), wall.n, false);
  }
  void AddDoor(const Wall& wall, double center, double width, double height) {
    if (width < 0.2 || height < 0.5) return;
    const Vector3d o = wall.origin + (center - 0.5 * width) * wall.dir;
    AddFramedOpening(o, width * wall.dir, height * Vector3d::UnitZ(), wall.n, true);
  }

  // A closed box [x0, x1] x [y0, y1] x [0, height] seen from inside: floor, ceiling and four
  // walls (planes, patches, the 12 edges). Returns the walls, counter-clockwise from y = y0.
  std::vector<Wall> AddInteriorBox(double x0, double x1, double y0, double y1, double height) {
    const Vector3d ex = Vector3d::UnitX(), ey = Vector3d::UnitY(), ez = Vector3d::UnitZ();
    const double lx = x1 - x0, ly = y1 - y0;
    const int floor_id = AddPlane(ez, Vector3d(0, 0, 0));
    AddPatch(Vector3d(x0, y0, 0), lx * ex, ly * ey, floor_id);
    const int ceiling_id = AddPlane(-ez, Vector3d(0, 0, height));
    AddPatch(Vector3d(x0, y0, height), lx * ex, ly * ey, ceiling_id);
    std::vector<Wall> walls = {
        {Vector3d(x0, y0, 0), ex, lx, ey, -1},
        {Vector3d(x1, y0, 0), ey, ly, -ex, -1},
        {Vector3d(x1, y1, 0), -ex, lx, -ey, -1},
        {Vector3d(x0, y1, 0), -ey, ly, ex, -1},
    };
    for (Wall& wall : walls) {
      wall.plane_id = AddPlane(wall.n, wall.origin);
      AddPatch(wall.origin, wall.length * wall.dir, height * ez, wall.plane_id);
      const Vector3d end = wall.origin + wall.length * wall.dir;
      AddSegment(wall.origin, end);                              // floor edge
      AddSegment(wall.origin + height * ez, end + height * ez);  // ceiling edge
      AddSegment(wall.origin, wall.origin + height * ez);        // vertical corner
    }
    return walls;
  }

  // Windows in slots of about slot_width along the wall (each with probability `fill`, else a
  // picture), skipping the slot `skip`.
  void AddWindowRow(const Wall& wall, double slot_width, double fill, double height, int skip) {
    const int slots = std::max(1, static_cast<int>(wall.length / slot_width));
    const double sw = wall.length / slots;
    for (int k = 0; k < slots; ++k) {
      const double draw = Uniform(0.0, 1.0);
      const double width = Uniform(0.7, std::min(1.4, sw - 0.5));
      const double sill = Uniform(0.8, 1.0);
      const double h = Uniform(0.8, std::min(1.3, height - sill - 0.3));
      const double jitter = std::max(0.0, 0.5 * (sw - width) - 0.2);
      const double center = (k + 0.5) * sw + Uniform(-jitter, jitter);
      if (k == skip) continue;
      if (draw <= fill) {
        AddWindow(wall, center, std::min(width, sw - 0.4), sill, std::min(h, height - sill - 0.3));
      } else {
        // A picture (flush rectangle) instead of the window.
        const double pw = std::min(0.6 * width, sw - 0.4), ph = std::min(0.6, height - 1.6);
        if (pw > 0.2 && ph > 0.2) {
          AddOutline(wall.origin + (center - 0.5 * pw) * wall.dir + 1.3 * Vector3d::UnitZ(),
                     pw * wall.dir, ph * Vector3d::UnitZ());
        }
      }
    }
  }

  double TotalPatchArea() const {
    double area = 0.0;
    for (const Patch& p : patches_) area += p.u.cross(p.v).norm();
    return area;
  }

  // Scatters n points on the patches, proportionally to their areas.
  void ScatterPoints(int n) {
    if (n <= 0 || patches_.empty()) return;
    std::vector<double> areas;
    for (const Patch& p : patches_) areas.push_back(p.u.cross(p.v).norm());
    std::discrete_distribution<int> pick(areas.begin(), areas.end());
    for (int i = 0; i < n; ++i) {
      const Patch& p = patches_[pick(*rng_)];
      const double a = Uniform(0.0, 1.0), b = Uniform(0.0, 1.0);
      scene_->points_w.push_back(p.origin + a * p.u + b * p.v);
      scene_->point_plane_ids.push_back(p.plane_id);
    }
  }

 private:
  Scene* scene_;
  double frame_depth_;
  std::mt19937_64* rng_;
  std::vector<Patch> patches_;
};

Eigen::AlignedBox3d ShrunkBox(const Vector3d& lo, const Vector3d& hi, const Vector3d& margin) {
  Vector3d m = margin;
  for (int i = 0; i < 3; ++i) m(i) = std::min(m(i), 0.45 * (hi(i) - lo(i)));
  return Eigen::AlignedBox3d(lo + m, hi - m);
}

void MakeRoom(double length, double width, double height, SceneBuilder* b) {
  const std::vector<Wall> walls =
      b->AddInteriorBox(-0.5 * length, 0.5 * length, -0.5 * width, 0.5 * width, height);
  // A door on a random wall (in a random slot), windows in the other slots.
  const int door_wall = b->UniformInt(0, 3);
  for (int k = 0; k < 4; ++k) {
    const Wall& wall = walls[k];
    const double slot_width = 2.0;
    const int slots = std::max(1, static_cast<int>(wall.length / slot_width));
    int skip = -1;
    if (k == door_wall) {
      skip = b->UniformInt(0, slots - 1);
      const double sw = wall.length / slots;
      b->AddDoor(wall, (skip + 0.5) * sw, std::min(0.9, sw - 0.4), std::min(2.1, height - 0.3));
    }
    b->AddWindowRow(wall, slot_width, 0.7, height, skip);
  }
  // Two ceiling lights.
  for (double sx : {-0.25, 0.25}) {
    const double lw = std::min(1.2, 0.3 * length), ld = std::min(0.3, 0.3 * width);
    b->AddOutline(Vector3d(sx * length - 0.5 * lw, -0.5 * ld, height), lw * Vector3d::UnitX(),
                  ld * Vector3d::UnitY());
  }
}

void MakeCorridor(double length, double width, double height, SceneBuilder* b) {
  const std::vector<Wall> walls =
      b->AddInteriorBox(-0.5 * length, 0.5 * length, -0.5 * width, 0.5 * width, height);
  // Doors along the long walls (0 and 2), a window in each end wall (1 and 3).
  for (int k : {0, 2}) {
    const Wall& wall = walls[k];
    const int slots = std::max(1, static_cast<int>(wall.length / 3.5));
    const double sw = wall.length / slots;
    for (int s = 0; s < slots; ++s) {
      const double draw = b->Uniform(0.0, 1.0);
      const double center = (s + 0.5) * sw + b->Uniform(-0.3 * sw, 0.3 * sw);
      if (draw < 0.65) {
        b->AddDoor(wall, center, std::min(0.9, sw - 0.4), std::min(2.1, height - 0.3));
      }
    }
  }
  for (int k : {1, 3}) {
    const Wall& wall = walls[k];
    const double w = std::min(1.2, wall.length - 0.6);
    const double sill = std::min(0.9, 0.3 * height);
    b->AddWindow(wall, 0.5 * wall.length, w, sill, std::min(1.2, height - sill - 0.3));
  }
  // Ceiling lights every 3 m across the corridor.
  const int lights = std::max(1, static_cast<int>(length / 3.0));
  for (int i = 0; i < lights; ++i) {
    const double x = -0.5 * length + (i + 0.5) * length / lights;
    const double lw = std::min(0.3, 0.1 * length / lights), ld = std::min(1.0, 0.6 * width);
    b->AddOutline(Vector3d(x - 0.5 * lw, -0.5 * ld, height), lw * Vector3d::UnitX(),
                  ld * Vector3d::UnitY());
  }
}

// A street along x between two rows of buildings whose fronts share the planes y = +-width/2.
void MakeFacades(double length, double width, double max_height, SceneBuilder* b) {
  const Vector3d ex = Vector3d::UnitX(), ey = Vector3d::UnitY(), ez = Vector3d::UnitZ();
  const int ground_id = b->AddPlane(ez, Vector3d::Zero());
  b->AddPatch(Vector3d(-0.5 * length, -0.5 * width, 0), length * ex, width * ey, ground_id);
  for (double side : {-1.0, 1.0}) {
    const double y = side * 0.5 * width;
    const Vector3d n = -side * ey;  // towards the street
    const int plane_id = b->AddPlane(n, Vector3d(0, y, 0));
    // Building extents along x; the last building absorbs a short remainder.
    std::vector<double> cuts = {-0.5 * length};
    while (0.5 * length - cuts.back() > 0) {
      double next = cuts.back() + b->Uniform(8.0, 14.0);
      if (0.5 * length - next < 4.0) next = 0.5 * length;
      cuts.push_back(next);
    }
    double previous_height = 0.0;
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
      const double xa = cuts[i], xb = cuts[i + 1], bw = xb - xa;
      const double h = b->Uniform(std::min(6.0, max_height), max_height);
      // The wall as seen from the street: left to right along `dir`.
      const Vector3d dir = side > 0 ? Vector3d(-ex) : Vector3d(ex);
      const Vector3d origin(side > 0 ? xb : xa, y, 0);
      const Wall wall{origin, dir, bw, n, plane_id};
      b->AddPatch(Vector3d(xa, y, 0), bw * ex, h * ez, plane_id);
      b->AddSegment(Vector3d(xa, y, h), Vector3d(xb, y, h));  // roof line
      b->AddSegment(Vector3d(xa, y, 0), Vector3d(xb, y, 0));  // foot of the facade
      b->AddSegment(Vector3d(xa, y, 0), Vector3d(xa, y, std::max(h, previous_height)));
      if (i + 2 == cuts.size()) b->AddSegment(Vector3d(xb, y, 0), Vector3d(xb, y, h));
      previous_height = h;
      // Ground floor: a door and a shop window.
      const double door_at = b->Uniform(1.2, std::max(1.2, bw - 1.2));
      b->AddDoor(wall, door_at, std::min(1.2, bw - 0.6), std::min(2.4, h - 0.5));
      const double shop_w = b->Uniform(2.0, 3.0);
      const double shop_at = door_at < 0.5 * bw ? door_at + 1.0 + 0.6 * shop_w + 0.2
                                                : door_at - 1.0 - 0.6 * shop_w - 0.2;
      if (shop_at - 0.5 * shop_w > 0.3 && shop_at + 0.5 * shop_w < bw - 0.3) {
        b->AddWindow(wall, shop_at, shop_w, 0.5, std::min(1.8, h - 1.0));
      }
      // Upper floors: a grid of windows, 3 m per floor, about 2.5 m per column.
      const double ww = b->Uniform(1.0, 1.4), wh = b->Uniform(1.2, 1.6);
      const int columns = std::max(1, static_cast<int>((bw - 1.0) / 2.5));
      for (int f = 1; 3.0 * f + 0.9 + wh <= h - 0.4; ++f) {
        for (int c = 0; c < columns; ++c) {
          b->AddWindow(wall, 0.5 + (c + 0.5) * (bw - 1.0) / columns, ww, 3.0 * f + 0.9, wh);
        }
      }
    }
  }
}

double OrDefault(double value, double fallback) { return value == 0.0 ? fallback : value; }

}  // namespace

Scene MakeScene(const SceneOptions& options, std::uint64_t seed) {
  double length = 0, width = 0, height = 0;
  switch (options.kind) {
    case SceneKind::kRoom:
      length = OrDefault(options.length, 8.0);
      width = OrDefault(options.width, 6.0);
      height = OrDefault(options.height, 3.0);
      break;
    case SceneKind::kCorridor:
      length = OrDefault(options.length, 30.0);
      width = OrDefault(options.width, 2.4);
      height = OrDefault(options.height, 2.8);
      break;
    case SceneKind::kFacades:
      length = OrDefault(options.length, 40.0);
      width = OrDefault(options.width, 12.0);
      height = OrDefault(options.height, 18.0);
      break;
  }
  for (double v : {length, width, height}) {
    if (!std::isfinite(v) || v <= 0.0) {
      throw std::invalid_argument("MakeScene: sizes must be finite and positive");
    }
  }
  if (options.num_points < -1) throw std::invalid_argument("MakeScene: num_points < -1");

  if (!std::isfinite(options.frame_depth) || options.frame_depth < 0.0 ||
      !std::isfinite(options.wall_margin) || options.wall_margin < 0.0) {
    throw std::invalid_argument("MakeScene: frame_depth and wall_margin must be finite, >= 0");
  }

  Scene scene;
  scene.kind = options.kind;
  std::mt19937_64 rng(seed);
  SceneBuilder builder(&scene, options.frame_depth, &rng);
  const double m = options.wall_margin;
  switch (options.kind) {
    case SceneKind::kRoom:
      MakeRoom(length, width, height, &builder);
      scene.free_space_w =
          ShrunkBox(Vector3d(-0.5 * length, -0.5 * width, 0),
                    Vector3d(0.5 * length, 0.5 * width, height), Vector3d(m, m, m));
      break;
    case SceneKind::kCorridor:
      MakeCorridor(length, width, height, &builder);
      scene.free_space_w =
          ShrunkBox(Vector3d(-0.5 * length, -0.5 * width, 0),
                    Vector3d(0.5 * length, 0.5 * width, height), Vector3d(std::max(m, 1.5), m, m));
      break;
    case SceneKind::kFacades:
      MakeFacades(length, width, height, &builder);
      scene.free_space_w = ShrunkBox(Vector3d(-0.5 * length, -0.5 * width, 0.0),
                                     Vector3d(0.5 * length, 0.5 * width, 3.5),
                                     Vector3d(std::max(m, 3.0), std::max(m, 1.5), 0.5));
      break;
  }
  // Default densities give about 600 / 800 / 1500 points at the default sizes.
  const double default_density[3] = {600.0 / 180.0, 800.0 / 325.44, 1.04};
  const double num_points =
      options.num_points >= 0
          ? options.num_points
          : std::round(default_density[static_cast<int>(options.kind)] * builder.TotalPatchArea());
  if (num_points > 1e7) throw std::invalid_argument("MakeScene: more than 1e7 points");
  builder.ScatterPoints(static_cast<int>(num_points));
  return scene;
}

}  // namespace sim
}  // namespace plucker
