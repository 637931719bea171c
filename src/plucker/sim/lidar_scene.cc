#include "plucker/sim/lidar_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace plucker {
namespace sim {
namespace {

constexpr double kEps = 1e-12;
constexpr int kGroundId = -2;

Eigen::Matrix3d RotZ(double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  Eigen::Matrix3d R;
  R << c, -s, 0, s, c, 0, 0, 0, 1;
  return R;
}

// Uniform double in [0, 1) from a 64-bit engine (portable, unlike std::uniform_real_distribution).
double Uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }
double Uniform(std::mt19937_64& rng, double lo, double hi) { return lo + (hi - lo) * Uniform(rng); }

}  // namespace

std::optional<RayHit> IntersectRectangle(const Rectangle& r, const Eigen::Vector3d& origin,
                                         const Eigen::Vector3d& dir, double t_min, double t_max) {
  const Eigen::Vector3d n = r.u.cross(r.v);
  const double denom = n.dot(dir);
  if (std::abs(denom) < kEps) return std::nullopt;
  const double t = n.dot(r.center - origin) / denom;
  if (!(t > t_min && t <= t_max)) return std::nullopt;
  const Eigen::Vector3d q = origin + t * dir - r.center;
  if (std::abs(r.u.dot(q)) > r.half_u || std::abs(r.v.dot(q)) > r.half_v) return std::nullopt;
  RayHit hit;
  hit.distance = t;
  hit.normal = denom < 0 ? n : Eigen::Vector3d(-n);
  return hit;
}

namespace {

// IntersectBox with the yaw's cosine and sine precomputed.
std::optional<RayHit> IntersectBoxCS(const Box& b, double c, double s,
                                     const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                                     double t_min, double t_max) {
  const Eigen::Vector3d q = origin - b.center;
  const Eigen::Vector3d o(c * q.x() + s * q.y(), -s * q.x() + c * q.y(), q.z());
  const Eigen::Vector3d d(c * dir.x() + s * dir.y(), -s * dir.x() + c * dir.y(), dir.z());
  double t_near = -std::numeric_limits<double>::infinity();
  double t_far = std::numeric_limits<double>::infinity();
  int axis_near = -1, axis_far = -1;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < kEps) {
      if (std::abs(o[a]) > b.half_size[a]) return std::nullopt;
      continue;
    }
    double t0 = (-b.half_size[a] - o[a]) / d[a];
    double t1 = (b.half_size[a] - o[a]) / d[a];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_near) t_near = t0, axis_near = a;
    if (t1 < t_far) t_far = t1, axis_far = a;
    if (t_near > t_far) return std::nullopt;
  }
  double t;
  int axis;
  if (t_near > t_min && t_near <= t_max) {
    t = t_near, axis = axis_near;
  } else if (t_far > t_min && t_far <= t_max) {
    t = t_far, axis = axis_far;  // origin inside the box
  } else {
    return std::nullopt;
  }
  if (axis < 0) return std::nullopt;
  Eigen::Vector3d n_box = Eigen::Vector3d::Zero();
  n_box[axis] = d[axis] > 0 ? -1.0 : 1.0;  // facing the ray origin
  RayHit hit;
  hit.distance = t;
  hit.normal =
      Eigen::Vector3d(c * n_box.x() - s * n_box.y(), s * n_box.x() + c * n_box.y(), n_box.z());
  return hit;
}

}  // namespace

std::optional<RayHit> IntersectBox(const Box& b, const Eigen::Vector3d& origin,
                                   const Eigen::Vector3d& dir, double t_min, double t_max) {
  return IntersectBoxCS(b, std::cos(b.yaw), std::sin(b.yaw), origin, dir, t_min, t_max);
}

std::optional<RayHit> IntersectCylinder(const Cylinder& c, const Eigen::Vector3d& origin,
                                        const Eigen::Vector3d& dir, double t_min, double t_max) {
  std::optional<RayHit> best;
  auto consider = [&](double t, const Eigen::Vector3d& n) {
    if (t > t_min && t <= t_max && (!best || t < best->distance)) {
      RayHit h;
      h.distance = t;
      h.normal = n.dot(dir) > 0 ? Eigen::Vector3d(-n) : n;
      best = h;
    }
  };
  const Eigen::Vector2d o(origin.x() - c.center.x(), origin.y() - c.center.y());
  const Eigen::Vector2d d = dir.head<2>();
  const double a = d.squaredNorm();
  if (a > kEps) {
    const double bh = o.dot(d);
    const double cc = o.squaredNorm() - c.radius * c.radius;
    const double disc = bh * bh - a * cc;
    if (disc >= 0) {
      const double sq = std::sqrt(disc);
      for (double t : {(-bh - sq) / a, (-bh + sq) / a}) {
        const double z = origin.z() + t * dir.z();
        if (z >= c.z_min && z <= c.z_max) {
          const Eigen::Vector2d p = o + t * d;
          consider(t, Eigen::Vector3d(p.x(), p.y(), 0.0) / c.radius);
        }
      }
    }
  }
  if (std::abs(dir.z()) > kEps) {  // caps
    for (double zc : {c.z_min, c.z_max}) {
      const double t = (zc - origin.z()) / dir.z();
      if ((o + t * d).squaredNorm() <= c.radius * c.radius) consider(t, Eigen::Vector3d::UnitZ());
    }
  }
  return best;
}

LidarScene::LidarScene(double ground_z, double grid_cell) : ground_z_(ground_z), cell_(grid_cell) {
  if (!(grid_cell > 0)) throw std::invalid_argument("LidarScene: grid cell must be positive");
}

int LidarScene::AddRectangle(const Rectangle& r) {
  kinds_.push_back(Kind::kRectangle);
  index_.push_back(static_cast<int>(rectangles_.size()));
  rectangles_.push_back(r);
  built_ = false;
  return static_cast<int>(kinds_.size()) - 1;
}
int LidarScene::AddBox(const Box& b) {
  kinds_.push_back(Kind::kBox);
  index_.push_back(static_cast<int>(boxes_.size()));
  boxes_.push_back(b);
  box_cos_sin_.emplace_back(std::cos(b.yaw), std::sin(b.yaw));
  built_ = false;
  return static_cast<int>(kinds_.size()) - 1;
}
int LidarScene::AddCylinder(const Cylinder& c) {
  kinds_.push_back(Kind::kCylinder);
  index_.push_back(static_cast<int>(cylinders_.size()));
  cylinders_.push_back(c);
  built_ = false;
  return static_cast<int>(kinds_.size()) - 1;
}

void LidarScene::Bounds(int id, Eigen::Vector2d* lo, Eigen::Vector2d* hi) const {
  lo->setConstant(std::numeric_limits<double>::infinity());
  hi->setConstant(-std::numeric_limits<double>::infinity());
  auto add = [&](const Eigen::Vector2d& p) {
    *lo = lo->cwiseMin(p);
    *hi = hi->cwiseMax(p);
  };
  switch (kinds_[id]) {
    case Kind::kRectangle: {
      const Rectangle& r = rectangles_[index_[id]];
      for (double a : {-r.half_u, r.half_u}) {
        for (double b : {-r.half_v, r.half_v}) add((r.center + a * r.u + b * r.v).head<2>());
      }
      break;
    }
    case Kind::kBox: {
      const Box& b = boxes_[index_[id]];
      const Eigen::Matrix3d R = RotZ(b.yaw);
      for (double sx : {-1.0, 1.0}) {
        for (double sy : {-1.0, 1.0}) {
          add((b.center + R * Eigen::Vector3d(sx * b.half_size.x(), sy * b.half_size.y(), 0))
                  .head<2>());
        }
      }
      break;
    }
    case Kind::kCylinder: {
      const Cylinder& c = cylinders_[index_[id]];
      add(c.center - Eigen::Vector2d::Constant(c.radius));
      add(c.center + Eigen::Vector2d::Constant(c.radius));
      break;
    }
  }
}

void LidarScene::Build() {
  unbounded_.clear();
  cell_start_.clear();
  cell_items_.clear();
  nx_ = ny_ = 0;
  built_ = true;
  if (kinds_.empty()) return;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  std::vector<Eigen::Vector2d> los(kinds_.size()), his(kinds_.size());
  for (int id = 0; id < static_cast<int>(kinds_.size()); ++id) {
    Bounds(id, &los[id], &his[id]);
    lo = lo.cwiseMin(los[id]);
    hi = hi.cwiseMax(his[id]);
  }
  grid_min_ = lo - Eigen::Vector2d::Constant(1e-6);
  nx_ = std::max(1, static_cast<int>(std::ceil((hi.x() - grid_min_.x()) / cell_)) + 1);
  ny_ = std::max(1, static_cast<int>(std::ceil((hi.y() - grid_min_.y()) / cell_)) + 1);
  if (static_cast<long long>(nx_) * ny_ > 16'000'000) {
    throw std::invalid_argument("LidarScene: scene too large for the grid cell size");
  }
  // Two passes (count, fill) into a CSR layout.
  std::vector<int> counts(static_cast<std::size_t>(nx_) * ny_ + 1, 0);
  auto cell_range = [&](int id, int* x0, int* y0, int* x1, int* y1) {
    *x0 = static_cast<int>(std::floor((los[id].x() - grid_min_.x()) / cell_));
    *y0 = static_cast<int>(std::floor((los[id].y() - grid_min_.y()) / cell_));
    *x1 = std::min(nx_ - 1, static_cast<int>(std::floor((his[id].x() - grid_min_.x()) / cell_)));
    *y1 = std::min(ny_ - 1, static_cast<int>(std::floor((his[id].y() - grid_min_.y()) / cell_)));
  };
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<int> fill;
    if (pass == 1) {
      cell_start_.assign(counts.size(), 0);
      for (std::size_t c = 1; c < counts.size(); ++c)
        cell_start_[c] = cell_start_[c - 1] + counts[c - 1];
      cell_items_.assign(cell_start_.back(), -1);
      fill.assign(cell_start_.begin(), cell_start_.end() - 1);
    }
    for (int id = 0; id < static_cast<int>(kinds_.size()); ++id) {
      int x0, y0, x1, y1;
      cell_range(id, &x0, &y0, &x1, &y1);
      if (static_cast<long long>(x1 - x0 + 1) * (y1 - y0 + 1) > 4096) {
        if (pass == 0) unbounded_.push_back(id);
        continue;
      }
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
          const int c = y * nx_ + x;
          if (pass == 0) {
            ++counts[c];
          } else {
            cell_items_[fill[c]++] = id;
          }
        }
      }
    }
  }
}

std::optional<RayHit> LidarScene::IntersectPrimitive(int id, const Eigen::Vector3d& origin,
                                                     const Eigen::Vector3d& dir, double t_min,
                                                     double t_max) const {
  std::optional<RayHit> h;
  switch (kinds_[id]) {
    case Kind::kRectangle:
      h = IntersectRectangle(rectangles_[index_[id]], origin, dir, t_min, t_max);
      break;
    case Kind::kBox:
      h = IntersectBoxCS(boxes_[index_[id]], box_cos_sin_[index_[id]].x(),
                         box_cos_sin_[index_[id]].y(), origin, dir, t_min, t_max);
      break;
    case Kind::kCylinder:
      h = IntersectCylinder(cylinders_[index_[id]], origin, dir, t_min, t_max);
      break;
  }
  if (h) h->primitive = id;
  return h;
}

std::optional<RayHit> LidarScene::Cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                                       double t_min, double t_max) const {
  std::optional<RayHit> best;
  double limit = t_max;
  auto consider = [&](const std::optional<RayHit>& h) {
    if (h && h->distance <= limit) {
      best = h;
      limit = h->distance;
    }
  };
  if (has_ground_ && std::abs(dir.z()) > kEps) {
    const double t = (ground_z_ - origin.z()) / dir.z();
    if (t > t_min && t <= limit) {
      RayHit h;
      h.distance = t;
      h.normal = Eigen::Vector3d(0.0, 0.0, origin.z() >= ground_z_ ? 1.0 : -1.0);
      h.primitive = kGroundId;
      consider(h);
    }
  }
  for (int id : unbounded_) consider(IntersectPrimitive(id, origin, dir, t_min, limit));
  if (!built_ || nx_ == 0) return best;

  // 2D DDA over the grid cells crossed by the ray's ground projection within (t_min, limit].
  const Eigen::Vector2d o = origin.head<2>(), d = dir.head<2>();
  const Eigen::Vector2d gmax = grid_min_ + cell_ * Eigen::Vector2d(nx_, ny_);
  double t0 = std::max(t_min, 0.0), t1 = limit;
  for (int a = 0; a < 2; ++a) {  // clip to the grid box
    if (std::abs(d[a]) < kEps) {
      if (o[a] < grid_min_[a] || o[a] > gmax[a]) return best;
      continue;
    }
    double ta = (grid_min_[a] - o[a]) / d[a], tb = (gmax[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (t0 > t1) return best;
  const Eigen::Vector2d p0 = o + t0 * d;
  int cx = std::clamp(static_cast<int>(std::floor((p0.x() - grid_min_.x()) / cell_)), 0, nx_ - 1);
  int cy = std::clamp(static_cast<int>(std::floor((p0.y() - grid_min_.y()) / cell_)), 0, ny_ - 1);
  const int step_x = d.x() > 0 ? 1 : -1, step_y = d.y() > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  auto next_boundary = [&](int c, int step, int a) {
    if (std::abs(d[a]) < kEps) return inf;
    const double edge = grid_min_[a] + cell_ * (c + (step > 0 ? 1 : 0));
    return (edge - o[a]) / d[a];
  };
  double t_next_x = next_boundary(cx, step_x, 0), t_next_y = next_boundary(cy, step_y, 1);
  const double dt_x = std::abs(d.x()) < kEps ? inf : cell_ / std::abs(d.x());
  const double dt_y = std::abs(d.y()) < kEps ? inf : cell_ / std::abs(d.y());
  for (int guard = 0; guard < nx_ + ny_ + 2; ++guard) {
    const int c = cy * nx_ + cx;
    for (int k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
      consider(IntersectPrimitive(cell_items_[k], origin, dir, t_min, limit));
    }
    const double t_exit = std::min(t_next_x, t_next_y);
    if (best && best->distance <= t_exit) break;
    if (t_exit > t1) break;
    if (t_next_x < t_next_y) {
      cx += step_x;
      t_next_x += dt_x;
      if (cx < 0 || cx >= nx_) break;
    } else {
      cy += step_y;
      t_next_y += dt_y;
      if (cy < 0 || cy >= ny_) break;
    }
  }
  return best;
}

namespace {

// A building: a box plus protruding floor ledges and vertical pilasters on its four facades
// (the relief between them plays the part of window recesses: vertical and horizontal edges).
void AddBuilding(LidarScene* scene, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                 double height, std::mt19937_64& rng) {
  Box b;
  b.center = Eigen::Vector3d(0.5 * (lo.x() + hi.x()), 0.5 * (lo.y() + hi.y()), 0.5 * height);
  b.half_size = Eigen::Vector3d(0.5 * (hi.x() - lo.x()), 0.5 * (hi.y() - lo.y()), 0.5 * height);
  scene->AddBox(b);
  const double depth = 0.3;
  const double floor_h = 3.2;
  const double pilaster_spacing = Uniform(rng, 5.0, 8.0);
  // Facades: for each side, the outward normal and the facade extent.
  for (int side = 0; side < 4; ++side) {
    const bool along_x = side < 2;  // facade runs along x (normal +-y)
    const double sign = (side % 2 == 0) ? -1.0 : 1.0;
    const double length = along_x ? hi.x() - lo.x() : hi.y() - lo.y();
    Eigen::Vector3d t_axis = along_x ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    Eigen::Vector3d n_axis = along_x ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
    const double face = along_x ? (sign < 0 ? lo.y() : hi.y()) : (sign < 0 ? lo.x() : hi.x());
    const double mid = along_x ? b.center.x() : b.center.y();
    // Floor ledges: full-length thin slabs every floor above the ground floor.
    for (double z = floor_h; z < height - 1.0; z += floor_h) {
      Box ledge;
      ledge.center = mid * t_axis + (face + sign * 0.5 * depth) * n_axis + Eigen::Vector3d(0, 0, z);
      ledge.half_size =
          0.5 * Eigen::Vector3d(along_x ? length : depth, along_x ? depth : length, 0.25);
      scene->AddBox(ledge);
    }
    // Pilasters: vertical strips, 0.6 m wide, full height.
    const int count = std::max(1, static_cast<int>(length / pilaster_spacing));
    for (int k = 1; k < count; ++k) {
      const double s = -0.5 * length + k * length / count;
      Box p;
      p.center = (mid + s) * t_axis + (face + sign * 0.5 * depth) * n_axis +
                 Eigen::Vector3d(0, 0, 0.5 * height);
      p.half_size = 0.5 * Eigen::Vector3d(along_x ? 0.6 : depth, along_x ? depth : 0.6, height);
      scene->AddBox(p);
    }
  }
}

}  // namespace

LidarScene MakeUrbanScene(const UrbanSceneOptions& opt) {
  if (opt.blocks_x < 1 || opt.blocks_y < 1 || !(opt.block_size > 10) || !(opt.street_width > 6)) {
    throw std::invalid_argument("MakeUrbanScene: invalid options");
  }
  std::mt19937_64 rng(opt.seed * 0x9E3779B97F4A7C15ull + 17);
  LidarScene scene(0.0, 8.0);
  scene.name = "urban";
  const double W = opt.street_width, B = opt.block_size, P = B + W;
  // Street centrelines at x = W/2 + i*P (i = 0..blocks_x), same in y. Block (i, j) spans
  // [W + i*P, W + i*P + B] in x.
  for (int i = 0; i < opt.blocks_x; ++i) {
    for (int j = 0; j < opt.blocks_y; ++j) {
      const Eigen::Vector2d lo(W + i * P, W + j * P);
      // 2 x 2 buildings per block separated by 4 m alleys (corners and depth discontinuities).
      const double half = 0.5 * (B - 4.0);
      for (int bi = 0; bi < 2; ++bi) {
        for (int bj = 0; bj < 2; ++bj) {
          const Eigen::Vector2d a = lo + Eigen::Vector2d(bi * (half + 4.0), bj * (half + 4.0));
          AddBuilding(&scene, a, a + Eigen::Vector2d(half, half), Uniform(rng, 8.0, 30.0), rng);
        }
      }
    }
  }
  // Poles and parked cars along both kerbs of every street segment, away from intersections.
  auto street_objects = [&](const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
    const Eigen::Vector2d dir = (to - from).normalized();
    const Eigen::Vector2d left(-dir.y(), dir.x());
    const double len = (to - from).norm();
    const double margin = 0.5 * W + 6.0;
    for (double side : {-1.0, 1.0}) {
      for (double s = margin; s < len - margin; s += opt.pole_spacing) {
        Cylinder c;
        c.center = from + s * dir + side * (0.5 * W - 1.0) * left;
        c.radius = Uniform(rng, 0.1, 0.25);
        c.z_max = Uniform(rng, 4.0, 8.0);
        scene.AddCylinder(c);
      }
      for (double s = margin + 5.0; s < len - margin; s += opt.car_spacing) {
        if (Uniform(rng) < 0.35) continue;  // empty slot
        Box car;
        const Eigen::Vector2d c = from + s * dir + side * (0.5 * W - 2.6) * left;
        car.center = Eigen::Vector3d(c.x(), c.y(), 0.85);
        car.half_size = Eigen::Vector3d(Uniform(rng, 2.0, 2.5), 0.9, 0.7);
        car.yaw = std::atan2(dir.y(), dir.x()) + Uniform(rng, -0.05, 0.05);
        scene.AddBox(car);
      }
    }
  };
  auto node = [&](int i, int j) { return Eigen::Vector2d(0.5 * W + i * P, 0.5 * W + j * P); };
  for (int j = 0; j <= opt.blocks_y; ++j) {
    for (int i = 0; i < opt.blocks_x; ++i) street_objects(node(i, j), node(i + 1, j));
  }
  for (int i = 0; i <= opt.blocks_x; ++i) {
    for (int j = 0; j < opt.blocks_y; ++j) street_objects(node(i, j), node(i, j + 1));
  }
  // Route: the outer ring with an S-shaped detour through the inner streets when there is room.
  const int bx = opt.blocks_x, by = opt.blocks_y;
  if (bx >= 3 && by >= 2) {
    scene.route = {node(0, 0),      node(bx, 0), node(bx, by), node(bx - 1, by),
                   node(bx - 1, 1), node(1, 1),  node(1, by),  node(0, by)};
  } else {
    scene.route = {node(0, 0), node(bx, 0), node(bx, by), node(0, by)};
  }
  scene.Build();
  return scene;
}

LidarScene MakeCorridorScene(const CorridorSceneOptions& opt) {
  if (!(opt.length > 20) || !(opt.width > 2) || !(opt.height > 2.5)) {
    throw std::invalid_argument("MakeCorridorScene: invalid options");
  }
  LidarScene scene(0.0, 8.0);
  scene.name = "corridor";
  const double L = opt.length, hw = 0.5 * opt.width, H = opt.height;
  Rectangle wall;
  wall.half_u = 0.5 * L;
  wall.half_v = 0.5 * H;
  wall.u = Eigen::Vector3d::UnitX();
  wall.v = Eigen::Vector3d::UnitZ();
  for (double y : {-hw, hw}) {
    wall.center = Eigen::Vector3d(0.5 * L, y, 0.5 * H);
    scene.AddRectangle(wall);
  }
  Rectangle ceiling;
  ceiling.center = Eigen::Vector3d(0.5 * L, 0.0, H);
  ceiling.half_u = 0.5 * L;
  ceiling.half_v = hw;
  scene.AddRectangle(ceiling);
  Rectangle end;
  end.u = Eigen::Vector3d::UnitY();
  end.v = Eigen::Vector3d::UnitZ();
  end.half_u = hw;
  end.half_v = 0.5 * H;
  for (double x : {0.0, L}) {
    end.center = Eigen::Vector3d(x, 0.0, 0.5 * H);
    scene.AddRectangle(end);
  }
  // Along the axis and back in a narrow loop (tight turns at the far ends). The route starts on
  // the first straight leg, 10 m from the end wall: the first frames drive straight (a start in
  // the corner turned tens of degrees between the first two scans) and see the end wall, which
  // fixes the speed before the featureless middle of the corridor.
  const double off = std::min(1.0, 0.3 * hw);
  scene.route = {Eigen::Vector2d(10.0, -off), Eigen::Vector2d(L - 5.0, -off),
                 Eigen::Vector2d(L - 5.0, off), Eigen::Vector2d(5.0, off),
                 Eigen::Vector2d(5.0, -off)};
  scene.Build();
  return scene;
}

LidarScene MakeScene(const std::string& name, std::uint64_t seed) {
  if (name == "urban") {
    UrbanSceneOptions o;
    o.seed = seed;
    return MakeUrbanScene(o);
  }
  if (name == "corridor") {
    CorridorSceneOptions o;
    o.seed = seed;
    return MakeCorridorScene(o);
  }
  if (name == "highway") {
    HighwaySceneOptions o;
    o.seed = seed;
    return MakeHighwayScene(o);
  }
  throw std::invalid_argument("unknown scene '" + name + "' (expected urban, corridor or highway)");
}

}  // namespace sim
}  // namespace plucker
