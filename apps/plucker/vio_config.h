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
  // The T_b_c to use instead of the input's (rig.txt or sensor.yaml): [tx, ty, tz, qx, qy, qz,
  // qw], the camera in the body frame; empty: the input's.
  std::vector<double> T_b_c;
};

// The keys of --config, comma-separated (for --help).
std::string VioConfigKeys();

// Reads --config: a YAML map of keys. Unknown keys, wrong types and values out of range are
// io::IoError naming the file.
void ApplyVioConfig(const std::string& path, VioConfig* config);
// The same for YAML text (`name` stands for the file in the messages, e.g. the Python options).
void ApplyVioConfigYaml(const std::string& text, const std::string& name, VioConfig* config);

}  // namespace app
}  // namespace plucker
