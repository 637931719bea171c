// Whether a scan can come from the sensor the user named (`plucker lidar --sensor`): a cloud
// without rings and without a spinning order (Livox-like) given as a spinning sensor would get
// garbage rings and garbage LOAM features, silently.
#pragma once

#include <string>

#include "plucker/sensor/lidar_model.h"
#include "plucker/sensor/lidar_scan.h"

namespace plucker {
namespace lidar {

struct SensorCheck {
  bool ok = true;
  std::string reason;           // why not (names the sensor and the figures), "" when ok
  int scan_order_rings = 0;     // rings found from the firing order (no ring field)
  double on_beam_fraction = 0;  // points within a quarter beam spacing of a beam elevation
};

// A generic model accepts every scan. A spinning model accepts a scan whose ring field stays
// below its number of beams, or, without a ring field, whose firing order splits into 0.75 .. 1.25
// times its number of beams (KITTI .bin) or whose points lie, for >= 80 %, within a quarter of the
// beam spacing of a beam elevation (a uniform elevation spread gives 50 %).
SensorCheck CheckScanMatchesSensor(const LidarScan& scan, const sensor::LidarModel& model);

}  // namespace lidar
}  // namespace plucker
