#include "vio_config.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include <Eigen/Core>

#include "plucker/io/io_error.h"

namespace plucker {
namespace app {
namespace {

using Options = odometry::VisualInertialOdometryOptions;
using ConfigSetter = std::function<void(const YAML::Node&, VioConfig*)>;

template <typename T>
ConfigSetter Field(T Options::*member) {
  return [member](const YAML::Node& node, VioConfig* c) { c->odometry.*member = node.as<T>(); };
}

// One per option, in the order of --help.
const std::vector<std::pair<std::string, ConfigSetter>>& ConfigFields() {
  static const std::vector<std::pair<std::string, ConfigSetter>> fields = {
      {"use_lines", Field(&Options::use_lines)},
      {"point_stride", [](const YAML::Node& n, VioConfig* c) { c->point_stride = n.as<int>(); }},
      {"window", Field(&Options::window)},
      {"prior_on_poses_only", Field(&Options::prior_on_poses_only)},
      {"iterations", Field(&Options::iterations)},
      {"keyframe_parallax_px", Field(&Options::keyframe_parallax_px)},
      {"min_tracked", Field(&Options::min_tracked)},
      {"min_tracked_ratio", Field(&Options::min_tracked_ratio)},
      {"max_keyframe_interval_s", Field(&Options::max_keyframe_interval_s)},
      {"gyro_bias_prior_sigma", Field(&Options::gyro_bias_prior_sigma)},
      {"accel_bias_prior_sigma", Field(&Options::accel_bias_prior_sigma)},
      {"velocity_prior_sigma", Field(&Options::velocity_prior_sigma)},
      {"tracking_velocity_sigma", Field(&Options::tracking_velocity_sigma)},
      {"init_min_keyframes", Field(&Options::init_min_keyframes)},
      {"init_max_keyframes", Field(&Options::init_max_keyframes)},
      {"init_min_excitation", Field(&Options::init_min_excitation)},
      {"init_max_rotation_disagreement_deg", Field(&Options::init_max_rotation_disagreement_deg)},
      {"init_gyro_bias_bound", Field(&Options::init_gyro_bias_bound)},
      {"image_still_px", Field(&Options::image_still_px)},
      {"max_point_tracks", Field(&Options::max_point_tracks)},
      {"point_min_distance_px", Field(&Options::point_min_distance_px)},
      {"line_max_segments", Field(&Options::line_max_segments)},
      {"line_detection_scale", Field(&Options::line_detection_scale)},
      {"line_flow_samples", Field(&Options::line_flow_samples)},
      {"estimate_extrinsic", Field(&Options::estimate_extrinsic)},
      {"extrinsic_rotation_sigma", Field(&Options::extrinsic_rotation_sigma)},
      {"extrinsic_translation_sigma", Field(&Options::extrinsic_translation_sigma)},
      {"extrinsic_min_rotation_deg", Field(&Options::extrinsic_min_rotation_deg)},
      {"estimate_time_offset", Field(&Options::estimate_time_offset)},
      {"time_offset_s", Field(&Options::time_offset_s)},
      {"time_offset_prior_sigma_s", Field(&Options::time_offset_prior_sigma_s)},
      {"T_b_c", [](const YAML::Node& n, VioConfig* c) { c->T_b_c = n.as<std::vector<double>>(); }},
      {"max_imu_only_share",
       [](const YAML::Node& n, VioConfig* c) { c->max_imu_only_share = n.as<double>(); }},
  };
  return fields;
}

}  // namespace

std::string VioConfigKeys() {
  std::string keys;
  for (const auto& f : ConfigFields()) keys += (keys.empty() ? "" : ", ") + f.first;
  return keys;
}

void ApplyVioConfig(const std::string& path, VioConfig* c) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw io::IoError(path, "invalid YAML: " + e.msg);
  }
  if (root.IsNull()) return;
  if (!root.IsMap()) throw io::IoError(path, "expected a map of option: value");
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    const auto field = std::find_if(ConfigFields().begin(), ConfigFields().end(),
                                    [&](const auto& f) { return f.first == key; });
    if (field == ConfigFields().end()) throw io::IoError(path, "unknown option '" + key + "'");
    try {
      field->second(kv.second, c);
    } catch (const YAML::Exception&) {
      throw io::IoError(path, "option '" + key + "' has a value of the wrong type");
    }
  }
  const std::string problem = c->odometry.Problem();
  if (!problem.empty()) throw io::IoError(path, problem);
  if (c->point_stride < 1) throw io::IoError(path, "an option is out of range (point_stride >= 1)");
  if (!(c->max_imu_only_share >= 0.0 && c->max_imu_only_share <= 1.0))
    throw io::IoError(path, "max_imu_only_share must be in [0, 1]");
  const std::vector<double>& e = c->T_b_c;
  const bool finite = std::all_of(e.begin(), e.end(), [](double v) { return std::isfinite(v); });
  if (!e.empty() &&
      (e.size() != 7 || !finite || Eigen::Vector4d(e[3], e[4], e[5], e[6]).norm() < 1e-6)) {
    throw io::IoError(path,
                      "T_b_c must be 7 finite numbers [tx, ty, tz, qx, qy, qz, qw] with a non-zero "
                      "quaternion");
  }
}

}  // namespace app
}  // namespace plucker
