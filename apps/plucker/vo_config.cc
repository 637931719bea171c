#include "vo_config.h"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <type_traits>

namespace plucker {
namespace app {
namespace {

using Prior = window::SlidingWindowOptions::PriorBlocks;

struct Row {
  std::string key;
  std::string doc;
  std::function<void(const YAML::Node&, VoConfig*)> set;  // throws std::invalid_argument
};

template <typename T>
T Parse(const YAML::Node& n) {
  try {
    return n.as<T>();
  } catch (const YAML::Exception&) {
    const char* what = std::is_same<T, bool>::value  ? "true or false"
                       : std::is_same<T, int>::value ? "an integer"
                                                     : "a number";
    throw std::invalid_argument(std::string("expected ") + what + ", got '" + n.Scalar() + "'");
  }
}

// A scalar of type T in [lo, hi] written into the member `field` returns.
template <typename T, typename Field>
Row Value(const char* key, const char* doc, T lo, T hi, Field field) {
  return {key, doc, [field, lo, hi](const YAML::Node& n, VoConfig* c) {
            const T v = Parse<T>(n);
            if (!(v >= lo && v <= hi)) {
              std::ostringstream s;
              s << "value " << n.Scalar() << " out of range [" << lo << ", " << hi << "]";
              throw std::invalid_argument(s.str());
            }
            field(*c) = v;
          }};
}

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kMaxInt = std::numeric_limits<int>::max();

const std::vector<Row>& Table() {
  static const std::vector<Row> rows = {
      Value<int>("window.size", "keyframes in the window", 2, 1000,
                 [](VoConfig& c) -> int& { return c.window.window_size; }),
      Value<int>("window.iterations", "solver iterations per window solve", 1, 1000,
                 [](VoConfig& c) -> int& { return c.window.max_iterations; }),
      Value<int>("window.tracking_iterations", "iterations of the motion-only pose", 1, 1000,
                 [](VoConfig& c) -> int& { return c.window.max_tracking_iterations; }),
      Value<double>("window.keyframe_parallax_px", "keyframe at this median parallax [px]", 0.0,
                    kInf, [](VoConfig& c) -> double& { return c.window.keyframe_parallax_px; }),
      Value<int>("window.min_tracked", "keyframe under this many tracked landmarks", 0, kMaxInt,
                 [](VoConfig& c) -> int& { return c.window.min_tracked; }),
      Value<double>("window.min_tracked_ratio", "keyframe under this share tracked", 0.0, 1.0,
                    [](VoConfig& c) -> double& { return c.window.min_tracked_ratio; }),
      Value<double>("window.loss_scale", "Huber/Cauchy scale [sigmas]", 1e-9, kInf,
                    [](VoConfig& c) -> double& { return c.window.loss_scale; }),
      Value<double>("window.outlier_sigmas", "observations above this are culled", 1e-9, kInf,
                    [](VoConfig& c) -> double& { return c.window.outlier_sigmas; }),
      Value<bool>("window.use_lines", "lines in the window", false, true,
                  [](VoConfig& c) -> bool& { return c.window.use_lines; }),
      Value<bool>("window.keep_marginalized_lines", "keep k0's line information", false, true,
                  [](VoConfig& c) -> bool& { return c.window.keep_marginalized_lines; }),
      Value<bool>("window.retain_line_observer_poses",
                  "k0's pose kept while lines that stay have observations from it (false: those in "
                  "the prior)",
                  false, true,
                  [](VoConfig& c) -> bool& { return c.window.retain_line_observer_poses; }),
      Value<int>("window.max_retained_poses", "retained observer poses at most", 0, kMaxInt,
                 [](VoConfig& c) -> int& { return c.window.max_retained_poses; }),
      Value<bool>("window.retained_overflow_into_prior",
                  "lines of a retained pose beyond the maximum into the prior (false: dropped)",
                  false, true,
                  [](VoConfig& c) -> bool& { return c.window.retained_overflow_into_prior; }),
      Value<bool>("window.first_estimate_jacobians", "FEJ on the prior's blocks", false, true,
                  [](VoConfig& c) -> bool& { return c.window.first_estimate_jacobians; }),
      Value<bool>("window.condition_far_lines", "lines in their anchor frame", false, true,
                  [](VoConfig& c) -> bool& { return c.window.condition_far_lines; }),
      {"window.prior_on_poses_only", "poses-only prior (fast) instead of one on landmarks",
       [](const YAML::Node& n, VoConfig* c) {
         c->window.prior_blocks = Parse<bool>(n) ? Prior::kPoses : Prior::kLandmarks;
       }},
      Value<double>(
          "window.line_min_angle_deg", "angle between the planes of a new line [deg]", 0.0, 90.0,
          [](VoConfig& c) -> double& { return c.window.line_triangulation.min_plane_angle_deg; }),
      Value<double>(
          "window.point_min_parallax_deg", "parallax of a new point [deg]", 0.0, 90.0,
          [](VoConfig& c) -> double& { return c.window.point_triangulation.min_parallax_deg; }),
      Value<int>("init.max_gap", "frames searched for the second view of the start", 1, kMaxInt,
                 [](VoConfig& c) -> int& { return c.start.max_init_gap; }),
      Value<int>("init.min_common_tracks", "point tracks seen in both views of a start", 5, kMaxInt,
                 [](VoConfig& c) -> int& { return c.start.two_view.min_common_tracks; }),
      Value<int>("init.min_inliers", "essential-matrix inliers of a start", 5, kMaxInt,
                 [](VoConfig& c) -> int& { return c.start.two_view.min_inliers; }),
      Value<double>("init.min_parallax_px", "rotation-compensated parallax of a start [px]", 0.0,
                    kInf, [](VoConfig& c) -> double& { return c.start.two_view.min_parallax_px; }),
      Value<bool>("init.widest_pair", "start on the widest pair that passes, not the first", false,
                  true, [](VoConfig& c) -> bool& { return c.start.widest_init_pair; }),
      Value<bool>("init.multi_view", "frames between the two views as keyframes of the start",
                  false, true, [](VoConfig& c) -> bool& { return c.start.multi_view_start; }),
      Value<double>("init.max_chi2_z",
                    "accept a start whose chi-square (chi2 - dof) / sqrt(2 dof) is at most this",
                    -kInf, kInf, [](VoConfig& c) -> double& { return c.start.max_init_chi2_z; }),
      Value<int>("init.max_tries", "starts tried from one first view before the best is taken", 1,
                 kMaxInt, [](VoConfig& c) -> int& { return c.start.max_init_tries; }),
      Value<int>("points.max_tracks", "live point tracks kept", 1, kMaxInt,
                 [](VoConfig& c) -> int& { return c.frontend.points.target_count; }),
      Value<double>("points.min_distance_px", "between point tracks [px]", 0.0, kInf,
                    [](VoConfig& c) -> double& { return c.frontend.points.min_distance_px; }),
      Value<double>("points.ransac_threshold_px", "epipolar RANSAC threshold [px]", 1e-9, kInf,
                    [](VoConfig& c) -> double& { return c.frontend.points.ransac_threshold_px; }),
      Value<bool>("lines.enabled", "detect and track segments", false, true,
                  [](VoConfig& c) -> bool& { return c.frontend.use_lines; }),
      Value<int>("lines.max_segments", "longest segments kept per image (0: all)", 0, kMaxInt,
                 [](VoConfig& c) -> int& { return c.frontend.max_segments; }),
      Value<double>("lines.min_segment_px", "shorter segments are not tracked [px]", 0.0, kInf,
                    [](VoConfig& c) -> double& { return c.frontend.min_segment_px; }),
      Value<double>("lines.detection_scale", "image scale of the detection", 1e-3, 1.0,
                    [](VoConfig& c) -> double& { return c.frontend.detection_scale; }),
      Value<int>("lines.flow_samples", "points per segment followed by flow", 0, 1000,
                 [](VoConfig& c) -> int& { return c.frontend.lines.flow_samples; }),
      Value<int>("lines.max_lost_frames", "frames a line track may skip", 0, 1000,
                 [](VoConfig& c) -> int& { return c.frontend.lines.max_lost_frames; }),
  };
  return rows;
}

void Flatten(const YAML::Node& node, const std::string& prefix,
             std::vector<std::pair<std::string, YAML::Node>>* out) {
  for (const auto& kv : node) {
    const std::string key = prefix + kv.first.as<std::string>();
    if (kv.second.IsMap()) {
      Flatten(kv.second, key + ".", out);
    } else {
      out->emplace_back(key, kv.second);
    }
  }
}

}  // namespace

VoConfig FeaturesVoConfig() {
  VoConfig c;
  c.start.two_view.min_common_tracks =
      8;  // the scarce-point scenes have about 10 point tracks a frame
  c.start.two_view.min_inliers = 8;
  return c;
}

VoConfig ImageVoConfig() {
  VoConfig c;
  c.start.widest_init_pair = false;  // the start as measured on the KITTI clip: the first pair that
  c.start.multi_view_start = false;  // passes, two views
  c.start.max_init_tries = 1;
  c.window.line_triangulation.min_plane_angle_deg = 10.0;
  c.window.prior_blocks = Prior::kPoses;
  c.window.keyframe_parallax_px = 20.0;
  c.window.min_tracked_ratio = 0.2;
  c.frontend.points.target_count = 200;
  c.frontend.points.min_distance_px = 20.0;
  c.frontend.max_segments = 60;
  c.frontend.detection_scale = 0.5;
  c.frontend.lines.flow_samples = 3;
  return c;
}

std::vector<std::string> VoConfigKeys() {
  std::vector<std::string> keys;
  for (const Row& r : Table()) keys.push_back(r.key + ": " + r.doc);
  return keys;
}

void ApplyVoConfigYaml(const std::string& text, const std::string& name, VoConfig* config) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(name + ": not valid YAML: " + e.what());
  }
  if (root.IsNull()) return;
  if (!root.IsMap()) throw std::runtime_error(name + ": expected a mapping of options");
  std::vector<std::pair<std::string, YAML::Node>> entries;
  try {
    Flatten(root, "", &entries);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(name + ": " + e.what());
  }
  for (const auto& [key, node] : entries) {
    const Row* row = nullptr;
    for (const Row& r : Table())
      if (r.key == key) row = &r;
    if (row == nullptr) throw std::runtime_error(name + ": unknown key '" + key + "'");
    if (!node.IsScalar())
      throw std::runtime_error(name + ": key '" + key + "': expected a scalar value");
    try {
      row->set(node, config);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(name + ": key '" + key + "': " + e.what());
    }
  }
}

void LoadVoConfig(const std::string& path, VoConfig* config) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot read the config file");
  std::stringstream text;
  text << in.rdbuf();
  ApplyVoConfigYaml(text.str(), path, config);
}

}  // namespace app
}  // namespace plucker
