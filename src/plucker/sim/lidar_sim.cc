#include "plucker/sim/lidar_sim.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace plucker {
namespace sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

double WrapAngle(double a) {
  while (a > kPi) a -= 2 * kPi;
  while (a <= -kPi) a += 2 * kPi;
  return a;
}

// Portable standard normal sample (Box-Muller on the raw 64-bit engine output), so that a seed
// gives the same data with every standard library.
double Gaussian(std::mt19937_64& rng) {
  const double u1 = (static_cast<double>(rng() >> 11) + 1.0) * 0x1.0p-53;  // (0, 1]
  const double u2 = static_cast<double>(rng() >> 11) * 0x1.0p-53;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

}  // namespace

VehicleTrajectory::VehicleTrajectory(const std::vector<Eigen::Vector2d>& route,
                                     const VehicleTrajectoryOptions& options)
    : options_(options) {
  if (route.size() < 2 || !(options.speed > 0)) {
    throw std::invalid_argument("VehicleTrajectory: need >= 2 route points and speed > 0");
  }
  if (!(options.speed_variation >= 0.0 && options.speed_variation < options.speed) ||
      !(options.speed_period > 0.0)) {
    throw std::invalid_argument(
        "VehicleTrajectory: need 0 <= speed_variation < speed and speed_period > 0");
  }
  const std::size_t n = route.size();
  // For each corner k: the tangent points on the incoming / outgoing legs and the arc radius.
  std::vector<Eigen::Vector2d> enter(n), leave(n);
  std::vector<double> radius(n, 0.0), turn(n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector2d& prev = route[(k + n - 1) % n];
    const Eigen::Vector2d& cur = route[k];
    const Eigen::Vector2d& next = route[(k + 1) % n];
    const Eigen::Vector2d d_in = cur - prev, d_out = next - cur;
    if (d_in.norm() < 1e-6 || d_out.norm() < 1e-6) {
      throw std::invalid_argument("VehicleTrajectory: repeated route point");
    }
    const double a_in = std::atan2(d_in.y(), d_in.x()), a_out = std::atan2(d_out.y(), d_out.x());
    const double theta = WrapAngle(a_out - a_in);
    turn[k] = theta;
    if (std::abs(theta) < 1e-6 || std::abs(theta) > kPi - 1e-3) {
      enter[k] = leave[k] = cur;  // straight through (or a reversal: sharp)
      continue;
    }
    const double half_tan = std::tan(0.5 * std::abs(theta));
    const double max_tangent = 0.5 * std::min(d_in.norm(), d_out.norm());
    const double r = std::min(options.corner_radius, max_tangent / half_tan);
    radius[k] = r;
    enter[k] = cur - d_in.normalized() * r * half_tan;
    leave[k] = cur + d_out.normalized() * r * half_tan;
  }
  double s = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t k1 = (k + 1) % n;
    // Arc at corner k (from enter[k] to leave[k]).
    if (radius[k] > 0) {
      Segment arc;
      arc.arc = true;
      const Eigen::Vector2d d_in = (route[k] - route[(k + n - 1) % n]).normalized();
      const double h0 = std::atan2(d_in.y(), d_in.x());
      const double sign = turn[k] > 0 ? 1.0 : -1.0;
      arc.start = enter[k];
      arc.radius = radius[k];
      arc.angle0 = h0;
      arc.turn = sign;
      arc.center = enter[k] + sign * radius[k] * Eigen::Vector2d(-std::sin(h0), std::cos(h0));
      arc.length = radius[k] * std::abs(turn[k]);
      arc.s0 = s;
      s += arc.length;
      segments_.push_back(arc);
    }
    // Straight from leave[k] to enter[k+1].
    Segment line;
    line.start = leave[k];
    const Eigen::Vector2d d = enter[k1] - leave[k];
    line.length = d.norm();
    if (line.length < 1e-9) continue;
    line.dir = d / line.length;
    line.s0 = s;
    s += line.length;
    segments_.push_back(line);
  }
  total_length_ = s;
}

double VehicleTrajectory::DistanceAt(double t) const {
  if (options_.speed_variation == 0.0) return options_.speed * t;
  const double w = 2.0 * kPi / options_.speed_period;
  return options_.speed * t + options_.speed_variation / w * (1.0 - std::cos(w * t));
}

SE3d VehicleTrajectory::T_w_s(double t) const {
  double s = std::fmod(DistanceAt(t), total_length_);
  if (s < 0) s += total_length_;
  auto it = std::upper_bound(segments_.begin(), segments_.end(), s,
                             [](double v, const Segment& seg) { return v < seg.s0; });
  const Segment& seg = *(it == segments_.begin() ? it : it - 1);
  const double u = std::clamp(s - seg.s0, 0.0, seg.length);
  Eigen::Vector2d p;
  double heading;
  if (seg.arc) {
    heading = seg.angle0 + seg.turn * u / seg.radius;
    p = seg.center + seg.turn * seg.radius * Eigen::Vector2d(std::sin(heading), -std::cos(heading));
  } else {
    heading = std::atan2(seg.dir.y(), seg.dir.x());
    p = seg.start + u * seg.dir;
  }
  const double A = options_.pitch_roll_amplitude;
  const double roll = A * std::sin(0.7 * t), pitch = A * std::sin(0.45 * t + 1.0);
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  return SE3d(R, Eigen::Vector3d(p.x(), p.y(), options_.mount_height));
}

LidarSimOptions LidarSimOptionsFor(const sensor::LidarModel& sensor, double range_noise_sigma,
                                   bool distortion, std::uint64_t seed) {
  LidarSimOptions options;
  options.elevation_rad = sensor.elevation_rad;
  options.azimuth_steps = sensor.azimuth_steps;
  options.rate_hz = sensor.rate_hz;
  options.min_range = sensor.min_range;
  options.max_range = sensor.max_range;
  options.range_noise_sigma = range_noise_sigma;
  options.distortion = distortion;
  options.spinning = sensor.spinning;
  options.min_elevation_rad = sensor.min_elevation_rad;
  options.max_elevation_rad = sensor.max_elevation_rad;
  options.rays_per_scan = sensor.rays_per_scan;
  options.seed = seed;
  return options;
}

LidarSimulator::LidarSimulator(const LidarScene& scene, const LidarSimOptions& options)
    : scene_(scene), options_(options) {
  const bool pattern_ok =
      options.spinning
          ? !options.elevation_rad.empty() && options.azimuth_steps >= 8
          : options.rays_per_scan > 0 && options.max_elevation_rad > options.min_elevation_rad;
  if (!pattern_ok || !(options.rate_hz > 0) || !(options.max_range > options.min_range) ||
      !(options.range_noise_sigma >= 0)) {
    throw std::invalid_argument("LidarSimulator: invalid options");
  }
}

void LidarSimulator::CastRay(const SE3d& T, const Eigen::Vector3d& d_s, double noise,
                             LidarScan* scan) const {
  const Eigen::Vector3d d_w = T.RotationMatrix() * d_s;
  const std::optional<RayHit> hit =
      scene_.Cast(T.translation(), d_w, options_.min_range, options_.max_range);
  if (!hit) return;
  const double range = hit->distance + noise;
  if (range < options_.min_range || range > options_.max_range) return;
  scan->points.push_back(range * d_s);
  scan->intensity.push_back(static_cast<float>(std::abs(hit->normal.dot(d_w))));
}

LidarScan LidarSimulator::NonSpinningScan(const VehicleTrajectory& trajectory, double t0,
                                          std::size_t frame_index) const {
  const int n = options_.rays_per_scan;
  const double sweep = 1.0 / options_.rate_hz;
  std::mt19937_64 rng(options_.seed * 0x9E3779B97F4A7C15ull ^
                      (frame_index + 1) * 0xD1B54A32D192ED03ull);
  // R2 sequence (Roberts 2018): x_k = frac(k / g), y_k = frac(k / g^2), g the plastic number.
  constexpr double kG = 1.32471795724474602596;
  constexpr double kA1 = 1.0 / kG, kA2 = 1.0 / (kG * kG);
  const double lo = options_.min_elevation_rad, span = options_.max_elevation_rad - lo;
  LidarScan scan;
  scan.timestamp = t0;
  scan.points.reserve(n);
  const SE3d T_w_s0 = trajectory.T_w_s(t0);
  for (int k = 0; k < n; ++k) {
    const double kk = static_cast<double>(frame_index) * n + k;
    const double az = 2.0 * kPi * (0.5 + kk * kA1 - std::floor(0.5 + kk * kA1));
    const double el = lo + span * (0.5 + kk * kA2 - std::floor(0.5 + kk * kA2));
    const Eigen::Vector3d d_s(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                              std::sin(el));
    const double t = sweep * k / n;
    const double noise =
        options_.range_noise_sigma > 0 ? options_.range_noise_sigma * Gaussian(rng) : 0.0;
    const std::size_t before = scan.size();
    CastRay(options_.distortion ? trajectory.T_w_s(t0 + t) : T_w_s0, d_s, noise, &scan);
    if (options_.distortion && scan.size() > before) scan.time.push_back(t);
  }
  return scan;
}

LidarScan LidarSimulator::Scan(const VehicleTrajectory& trajectory, double t0,
                               std::size_t frame_index, LidarSimStats* stats) const {
  if (!options_.spinning) {
    LidarScan scan = NonSpinningScan(trajectory, t0, frame_index);
    if (stats) stats->rays = options_.rays_per_scan, stats->hits = scan.size();
    return scan;
  }
  const int A = options_.azimuth_steps;
  const int rings = static_cast<int>(options_.elevation_rad.size());
  const double sweep = 1.0 / options_.rate_hz;
  // Poses of every firing (one per azimuth step with distortion, else all the scan start).
  std::vector<SE3d> poses;
  const SE3d T_w_s0 = trajectory.T_w_s(t0);
  if (options_.distortion) {
    poses.reserve(A);
    for (int k = 0; k < A; ++k) poses.push_back(trajectory.T_w_s(t0 + sweep * k / A));
  }
  std::vector<double> cos_az(A), sin_az(A);
  for (int k = 0; k < A; ++k) {
    const double az = 2.0 * kPi * (k + 0.5) / A;  // from the front, counter-clockwise
    cos_az[k] = std::cos(az);
    sin_az[k] = std::sin(az);
  }
  std::mt19937_64 rng(options_.seed * 0x9E3779B97F4A7C15ull ^
                      (frame_index + 1) * 0xD1B54A32D192ED03ull);
  LidarScan scan;
  scan.timestamp = t0;
  scan.points.reserve(static_cast<std::size_t>(A) * rings / 2);
  std::size_t rays = 0;
  for (int r = 0; r < rings; ++r) {
    const double el = options_.elevation_rad[r];
    const double ce = std::cos(el), se = std::sin(el);
    for (int k = 0; k < A; ++k) {
      const Eigen::Vector3d d_s(ce * cos_az[k], ce * sin_az[k], se);
      ++rays;
      const double noise = options_.range_noise_sigma > 0
                               ? options_.range_noise_sigma * Gaussian(rng)
                               : 0.0;  // drawn per ray so the stream does not depend on hits
      const std::size_t before = scan.size();
      CastRay(options_.distortion ? poses[k] : T_w_s0, d_s, noise, &scan);
      if (scan.size() == before) continue;
      scan.ring.push_back(r);
      if (options_.distortion) scan.time.push_back(sweep * k / A);
    }
  }
  if (stats) {
    stats->rays = rays;
    stats->hits = scan.size();
  }
  return scan;
}

}  // namespace sim
}  // namespace plucker
