#include "plucker/sensor/lidar_model.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>
#include <stdexcept>

#include "plucker/geometry/fast_atan2.h"

namespace plucker {
namespace sensor {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

double Elevation(const Eigen::Vector3d& p) { return FastAtan2(p.z(), p.head<2>().norm()); }

std::vector<double> SortedRadians(std::vector<double> deg) {
  std::sort(deg.begin(), deg.end());
  for (double& d : deg) d *= kDeg;
  return deg;
}

// Wraps an angle difference into (-pi, pi].
double WrapAngle(double a) {
  while (a > kPi) a -= 2 * kPi;
  while (a <= -kPi) a += 2 * kPi;
  return a;
}

int CountRings(const std::vector<int>& ring) {
  std::set<int> distinct;
  for (int r : ring) {
    if (r >= 0) distinct.insert(r);
  }
  return static_cast<int>(distinct.size());
}

}  // namespace

int LidarModel::RingFromElevation(double e) const {
  const std::vector<double>& el = elevation_rad;
  if (el.empty() || !std::isfinite(e)) return -1;
  if (el.size() == 1) return std::abs(e - el[0]) < 1.0 * kDeg ? 0 : -1;
  const double half_low = 0.5 * (el[1] - el[0]);
  const double half_high = 0.5 * (el.back() - el[el.size() - 2]);
  if (e < el.front() - half_low || e > el.back() + half_high) return -1;
  const auto it = std::lower_bound(el.begin(), el.end(), e);
  if (it == el.begin()) return 0;
  if (it == el.end()) return static_cast<int>(el.size()) - 1;
  const int hi = static_cast<int>(it - el.begin());
  return (e - el[hi - 1] <= el[hi] - e) ? hi - 1 : hi;
}

LidarModel HDL64() {
  LidarModel m;
  m.name = "hdl64";
  std::vector<double> deg;
  for (int i = 0; i < 32; ++i) deg.push_back(2.0 - i * (2.0 + 8.33) / 31.0);      // upper block
  for (int i = 0; i < 32; ++i) deg.push_back(-8.83 - i * (24.33 - 8.83) / 31.0);  // lower block
  m.elevation_rad = SortedRadians(deg);
  m.min_range = 0.9;
  m.max_range = 120.0;
  m.azimuth_steps = 2083;
  m.rate_hz = 10.0;
  return m;
}

LidarModel VLP32() {
  LidarModel m;
  m.name = "vlp32";
  // VLP-32C vertical angles (degrees) from the manufacturer's table, in laser-id order.
  m.elevation_rad = SortedRadians({-25.0,  -1.0,  -1.667, -15.639, -11.31, 0.0,   -0.667, -8.843,
                                   -7.254, 0.333, -0.333, -6.148,  -5.333, 1.333, 0.667,  -4.0,
                                   -4.667, 1.667, 1.0,    -3.667,  -3.333, 3.333, 2.333,  -2.667,
                                   -3.0,   7.0,   4.667,  -2.333,  -2.0,   15.0,  10.333, -1.333});
  m.min_range = 0.5;
  m.max_range = 200.0;
  m.azimuth_steps = 1800;
  m.rate_hz = 10.0;
  return m;
}

LidarModel VLP16() {
  LidarModel m;
  m.name = "vlp16";
  std::vector<double> deg;
  for (int i = 0; i < 16; ++i) deg.push_back(-15.0 + 2.0 * i);
  m.elevation_rad = SortedRadians(deg);
  m.min_range = 0.5;
  m.max_range = 100.0;
  m.azimuth_steps = 1800;
  m.rate_hz = 10.0;
  return m;
}

namespace {

// Uniform beams over +-half_fov_deg (the OS1 datasheet: 16.6 deg for 64 beams, 22.5 for 128).
LidarModel OusterOS1(int beams, double half_fov_deg) {
  LidarModel m;
  m.name = "os1-" + std::to_string(beams);
  std::vector<double> deg;
  for (int i = 0; i < beams; ++i)
    deg.push_back(-half_fov_deg + 2.0 * half_fov_deg * i / (beams - 1));
  m.elevation_rad = SortedRadians(deg);
  m.min_range = 0.5;
  m.max_range = 120.0;
  m.azimuth_steps = 1024;
  m.rate_hz = 10.0;
  return m;
}

}  // namespace

LidarModel OS1_64() { return OusterOS1(64, 16.6); }
LidarModel OS1_128() { return OusterOS1(128, 22.5); }

LidarModel GenericLidar() {
  LidarModel m;
  m.name = "generic";
  m.spinning = false;
  m.min_elevation_rad = -25.0 * kDeg;
  m.max_elevation_rad = 15.0 * kDeg;
  m.rays_per_scan = 40000;
  m.min_range = 0.5;
  m.max_range = 100.0;
  m.azimuth_steps = 0;
  m.rate_hz = 10.0;
  return m;
}

const char* LidarModelNames() { return "hdl64, vlp32, vlp16, os1-64, os1-128, generic"; }

LidarModel LidarModelFromName(const std::string& name) {
  std::string n = name;
  for (char& c : n) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (n == "hdl64") return HDL64();
  if (n == "vlp32") return VLP32();
  if (n == "vlp16") return VLP16();
  if (n == "os1-64") return OS1_64();
  if (n == "os1-128") return OS1_128();
  if (n == "generic") return GenericLidar();
  throw std::invalid_argument("unknown sensor '" + name + "' (expected " + LidarModelNames() + ")");
}

RingAssignmentStats AssignRings(LidarScan* scan, const LidarModel& model) {
  RingAssignmentStats stats;
  if (scan->ring.size() == scan->size() && !scan->empty()) {
    stats.rings_found = CountRings(scan->ring);
    stats.unassigned =
        static_cast<std::size_t>(std::count(scan->ring.begin(), scan->ring.end(), -1));
    return stats;
  }
  scan->ring.resize(scan->size());
  for (std::size_t i = 0; i < scan->size(); ++i) {
    scan->ring[i] = model.RingFromElevation(Elevation(scan->points[i]));
    if (scan->ring[i] < 0) ++stats.unassigned;
  }
  stats.rings_found = CountRings(scan->ring);
  return stats;
}

namespace {

// The ring split below takes its decisions on the points' coordinates; a decision within this
// sine of its boundary is taken on FastAtan2's azimuths instead, as the definition states (their
// error, 1.7e-6 rad, lies far inside).
constexpr double kNearSine = 1e-4;

double Azimuth(const Eigen::Vector3d& p) { return FastAtan2(p.y(), p.x()); }

// The first point of each ring, for a sweep in direction kDir (+1: counter-clockwise) from the
// seam azimuth a0; and the steps between consecutive points that go in direction kDir less those
// that go against it (negative: the sweep runs the other way).
struct RingStarts {
  std::vector<std::size_t> starts;
  long forward_votes = 0;
};

// The definition (AssignRingsFromScanOrder, lidar_model.h) on u, the azimuth swept from the seam
// in [0, 2 pi): a ring ends where u drops by more than the threshold once the ring has reached
// u > pi (so that jitter around the seam does not split a ring, and rings with few returns still
// end at the seam). u is an angle of the rotated point (x', y') = R(-a0) (x, y), and with h = kDir
// y':
//   - u > pi exactly when h < 0;
//   - u drops from one point to the next only when the step goes backwards (kDir times the cross
//     product of the two points is negative) or crosses the seam forwards (h from < 0 to > 0).
// All other steps leave the ring as it is, so that the azimuths are computed only at those few
// steps and at the points near the line of the seam (|h| within kNearSine of the range), where
// they are compared as the definition says. (The L1 norm bounds the range: a safe margin.)
template <int kDir>
RingStarts SplitRings(const std::vector<Eigen::Vector3d>& p, double a0,
                      const ScanOrderOptions& options) {
  const double c = std::cos(a0), s = std::sin(a0);
  auto swept = [&](std::size_t i) {          // u from the azimuth
    double v = kDir * (Azimuth(p[i]) - a0);  // in (-4 pi, 4 pi): |azimuth|, |a0| < ~2 pi
    while (v < 0) v += 2 * kPi;
    while (v >= 2 * kPi) v -= 2 * kPi;
    return v;
  };
  RingStarts out;
  out.starts = {0};
  const auto min_points = static_cast<std::size_t>(options.min_points_per_ring);
  bool past_half = swept(0) > kPi;  // the current ring has reached u > pi
  double x_prev = p[0].x(), y_prev = p[0].y();
  double h_prev = kDir * (c * y_prev - s * x_prev);
  double margin_prev = kNearSine * (std::abs(x_prev) + std::abs(y_prev));
  bool near_prev = !(std::abs(h_prev) > margin_prev);  // also for NaN and the origin
  long votes = 0;
  for (std::size_t i = 1; i < p.size(); ++i) {
    const double x = p[i].x(), y = p[i].y();
    const double h = kDir * (c * y - s * x);
    const double margin = kNearSine * (std::abs(x) + std::abs(y));
    const bool near = !(std::abs(h) > margin);
    const double cross = kDir * (x_prev * y - y_prev * x);  // r_prev r sin(step)
    const double step_margin = margin_prev * (std::abs(x) + std::abs(y));
    const bool forward = cross > step_margin;
    votes += forward - (cross < -step_margin);
    if (near_prev | near | !forward | ((h_prev < 0.0) & (h > 0.0))) {
      const double u_prev = swept(i - 1), u = swept(i);
      if (u_prev - u > options.wrap_threshold_rad && past_half &&
          i - out.starts.back() >= min_points) {
        out.starts.push_back(i);
        past_half = u > kPi;
      } else {
        past_half |= u > kPi;
      }
    } else {
      past_half |= h < 0.0;
    }
    x_prev = x, y_prev = y, h_prev = h, margin_prev = margin, near_prev = near;
  }
  out.forward_votes = votes;
  return out;
}

RingStarts SplitRings(const std::vector<Eigen::Vector3d>& p, double dir, double a0,
                      const ScanOrderOptions& options) {
  return dir > 0 ? SplitRings<1>(p, a0, options) : SplitRings<-1>(p, a0, options);
}

// The sweep direction voted by the first steps: the split runs in it, and is run again in the
// other direction in the rare case that the whole scan votes otherwise.
double FirstGuessOfDirection(const std::vector<Eigen::Vector3d>& p) {
  long votes = 0;
  for (std::size_t i = 1; i < std::min<std::size_t>(p.size(), 4096); ++i) {
    const double cross = p[i - 1].x() * p[i].y() - p[i - 1].y() * p[i].x();
    votes += (cross > 0.0) - (cross < 0.0);
  }
  return votes >= 0 ? 1.0 : -1.0;
}

}  // namespace

RingAssignmentStats AssignRingsFromScanOrder(LidarScan* scan, const ScanOrderOptions& options) {
  RingAssignmentStats stats;
  const std::size_t n = scan->size();
  scan->ring.resize(n);  // every element is set below
  if (n == 0) return stats;
  const std::vector<Eigen::Vector3d>& p = scan->points;
  // The sweep direction: the sign that most steps between neighbours take.
  double dir = FirstGuessOfDirection(p);
  const double a0 = Azimuth(p[0]);
  RingStarts split = SplitRings(p, dir, a0, options);
  if (split.forward_votes < 0) split = SplitRings(p, dir = -dir, a0, options);
  // Each beam sweeps one turn starting at a seam azimuth (KITTI: the front, az ~ 0). The first
  // split takes the seam from the first point; if a ring starts behind it, the split is repeated
  // with the seam just before the earliest ring start, so that no ring start falls behind it.
  std::vector<std::size_t> starts = std::move(split.starts);
  double earliest = 0.0;  // offset of the earliest ring start from a0, in sweep direction
  for (std::size_t s : starts) earliest = std::min(earliest, dir * WrapAngle(Azimuth(p[s]) - a0));
  if (starts.size() > 1 && earliest < 0.0)
    starts = SplitRings(p, dir, a0 + dir * (earliest - 1e-6), options).starts;
  const int rings = static_cast<int>(starts.size());
  starts.push_back(n);
  for (int r = 0; r < rings; ++r)
    std::fill(scan->ring.begin() + starts[r], scan->ring.begin() + starts[r + 1], r);
  auto mean_elevation = [&](int r) {
    double sum = 0.0;
    for (std::size_t i = starts[r]; i < starts[r + 1]; ++i) sum += Elevation(scan->points[i]);
    return sum / static_cast<double>(starts[r + 1] - starts[r]);
  };
  // Ring 0 must be the lowest beam: flip when the stream runs from the top beam down.
  if (rings > 1 && mean_elevation(0) > mean_elevation(rings - 1)) {
    for (int& r : scan->ring) r = rings - 1 - r;
  }
  stats.rings_found = rings;
  return stats;
}

LidarModel AutoDetectSensor(const LidarScan& scan, double* confidence) {
  std::vector<double> el;
  el.reserve(scan.size());
  for (const Eigen::Vector3d& p : scan.points) {
    if (p.head<2>().norm() > 1.0) el.push_back(Elevation(p) / kDeg);
  }
  if (el.size() < 100) {
    if (confidence) *confidence = 0.0;
    return VLP16();
  }
  std::sort(el.begin(), el.end());
  const double lo = el[static_cast<std::size_t>(0.002 * el.size())];
  const double hi = el[static_cast<std::size_t>(0.998 * (el.size() - 1))];
  if (lo > -18.0) {  // VLP-16 reaches only -15 deg
    if (confidence) *confidence = (lo > -16.5 && hi < 16.5) ? 0.9 : 0.5;
    return VLP16();
  }
  if (hi > 5.0) {  // below -18 and above +5: only the VLP-32C spans both
    if (confidence) *confidence = 0.9;
    return VLP32();
  }
  // Both HDL-64E and a VLP-32C without upward returns: the HDL-64E lower block has a beam every
  // 0.5 deg down to -24.3, the VLP-32C only three beams below -8 deg. Count occupied 1-deg bins.
  const int first_bin = static_cast<int>(std::ceil(lo + 1.0)), last_bin = -10;
  int occupied = 0, bins = 0;
  const std::size_t min_count = std::max<std::size_t>(5, el.size() / 5000);
  for (int b = first_bin; b < last_bin; ++b) {
    ++bins;
    const auto a = std::lower_bound(el.begin(), el.end(), static_cast<double>(b));
    const auto e = std::lower_bound(el.begin(), el.end(), static_cast<double>(b + 1));
    if (static_cast<std::size_t>(e - a) >= min_count) ++occupied;
  }
  const double fill = bins > 0 ? static_cast<double>(occupied) / bins : 0.0;
  if (confidence) *confidence = std::abs(fill - 0.5) + 0.4;
  return fill > 0.5 ? HDL64() : VLP32();
}

}  // namespace sensor
}  // namespace plucker
