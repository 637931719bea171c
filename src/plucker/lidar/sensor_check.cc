#include "plucker/lidar/sensor_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace plucker {
namespace lidar {

namespace {

// The fraction of points (horizontal distance > 1 m) within a quarter of the local beam spacing
// of the nearest beam elevation of `model`.
double OnBeamFraction(const LidarScan& scan, const sensor::LidarModel& model) {
  const std::vector<double>& el = model.elevation_rad;
  if (el.size() < 2) return 0.0;
  std::size_t n = 0, on = 0;
  for (const Eigen::Vector3d& p : scan.points) {
    const double h = p.head<2>().norm();
    if (!(h > 1.0)) continue;
    ++n;
    const double e = std::atan2(p.z(), h);
    const int r = model.RingFromElevation(e);
    if (r < 0) continue;
    const int other = r + 1 < static_cast<int>(el.size()) ? r + 1 : r - 1;
    if (std::abs(e - el[r]) <= 0.25 * std::abs(el[other] - el[r])) ++on;
  }
  return n ? static_cast<double>(on) / static_cast<double>(n) : 0.0;
}

}  // namespace

SensorCheck CheckScanMatchesSensor(const LidarScan& scan, const sensor::LidarModel& model) {
  SensorCheck c;
  if (!model.spinning || scan.empty()) return c;
  const int beams = model.num_rings();
  char buf[320];
  if (scan.ring.size() == scan.size()) {
    const int max_ring = *std::max_element(scan.ring.begin(), scan.ring.end());
    if (max_ring < beams) return c;
    std::snprintf(buf, sizeof(buf), "the ring field goes up to %d; a %s has %d beams (0..%d)",
                  max_ring, model.name.c_str(), beams, beams - 1);
    c.ok = false;
    c.reason = buf;
    return c;
  }
  LidarScan copy;
  copy.points = scan.points;
  c.scan_order_rings = sensor::AssignRingsFromScanOrder(&copy).rings_found;
  if (c.scan_order_rings >= 0.75 * beams && c.scan_order_rings <= 1.25 * beams) return c;
  c.on_beam_fraction = OnBeamFraction(scan, model);
  if (c.on_beam_fraction >= 0.8) return c;
  std::snprintf(buf, sizeof(buf),
                "does not look like a %s cloud: no ring field, %d rings from the point order (a "
                "%s has %d) and only %.0f %% of the points on its beam elevations; a cloud "
                "without rings or spinning order needs --sensor generic",
                model.name.c_str(), c.scan_order_rings, model.name.c_str(), beams,
                100.0 * c.on_beam_fraction);
  c.ok = false;
  c.reason = buf;
  return c;
}

}  // namespace lidar
}  // namespace plucker
