// The options of `plucker vio` (docs/vio.md): the odometry's (odometry/visual_inertial_odometry.h)
// and the input's, set by name from --config FILE.yaml.
#pragma once

#include <string>
#include <vector>

#include "plucker/odometry/visual_inertial_odometry.h"

namespace plucker {
namespace app {

struct VioConfig {
  odometry::VisualInertialOdometryOptions odometry;
  int point_stride = 1;  // features folders: the point tracks whose id is a multiple of this
  // The largest share of the window's frames without a visual update (IMU only) of a run that
  // exits 0 (else exit code 3, docs/cli.md), in [0, 1].
  double max_imu_only_share = 0.2;
  // The T_b_c to use instead of the input's (rig.txt or sensor.yaml): [tx, ty, tz, qx, qy, qz,
  // qw], the camera in the body frame; empty: the input's.
  std::vector<double> T_b_c;
};

// The keys of --config, comma-separated (for --help).
std::string VioConfigKeys();

// Reads --config: a YAML map of keys. Unknown keys, wrong types and values out of range are
// io::IoError naming the file.
void ApplyVioConfig(const std::string& path, VioConfig* config);

}  // namespace app
}  // namespace plucker
