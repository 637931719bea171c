#include "lidar_options_table.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <utility>

namespace plucker {
namespace app {
namespace {

using lidar::DeskewMode;
using lidar::RingSource;
using lidar::RobustLoss;

// Shortest text that reads back as the same double ("0.1", not "0.10000000000000001"); integral
// values keep a ".0" so that the file shows they are real numbers.
std::string FormatNumber(double v) {
  char buf[64];
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof(buf), "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 1e15)
    std::snprintf(buf, sizeof(buf), "%.1f", v);  // 100.0, not 1e+02
  std::string s = buf;
  return s;
}

template <typename T>
struct Traits;
template <>
struct Traits<double> {
  static constexpr const char* kType = "number";
  static constexpr const char* kExpected = "a number";
  static std::string Format(double v) { return FormatNumber(v); }
};
template <>
struct Traits<int> {
  static constexpr const char* kType = "integer";
  static constexpr const char* kExpected = "an integer";
  static std::string Format(int v) { return std::to_string(v); }
};
template <>
struct Traits<bool> {
  static constexpr const char* kType = "bool";
  static constexpr const char* kExpected = "true or false";
  static std::string Format(bool v) { return v ? "true" : "false"; }
};

// A number, integer or bool option. `field` is a generic lambda returning the member of a
// (const) LidarConfig&, so the table names each member once.
template <typename Field>
LidarOption Option(const char* key, const char* unit, const char* doc, Field field) {
  using T = std::remove_reference_t<decltype(field(std::declval<LidarConfig&>()))>;
  LidarOption o{key, Traits<T>::kType, unit, doc, nullptr, nullptr};
  o.get = [field](const LidarConfig& c) { return Traits<T>::Format(field(c)); };
  o.set = [field](const YAML::Node& n, LidarConfig* c) {
    try {
      field(*c) = n.as<T>();
    } catch (const YAML::Exception&) {
      throw std::invalid_argument(std::string("expected ") + Traits<T>::kExpected + ", got '" +
                                  n.Scalar() + "'");
    }
  };
  return o;
}

// An enumeration, written by name.
template <typename Field, typename Enum>
LidarOption Choice(const char* key, const char* doc, Field field,
                   std::vector<std::pair<std::string, Enum>> names) {
  std::string type;
  for (const auto& [name, value] : names) type += (type.empty() ? "" : " | ") + name;
  LidarOption o{key, type, "", doc, nullptr, nullptr};
  o.get = [field, names](const LidarConfig& c) {
    for (const auto& [name, value] : names)
      if (value == field(c)) return name;
    throw std::logic_error("lidar options table: unnamed value of " + names.front().first);
  };
  o.set = [field, names, type](const YAML::Node& n, LidarConfig* c) {
    for (const auto& [name, value] : names) {
      if (n.Scalar() == name) {
        field(*c) = value;
        return;
      }
    }
    throw std::invalid_argument("expected " + type + ", got '" + n.Scalar() + "'");
  };
  return o;
}

#define PLUCKER_MEMBER(member) \
  [](auto& c) -> auto& { return c.member; }

std::vector<LidarOption> MakeTable() {
  std::vector<LidarOption> t;
  // features: lidar/features.h
  t.push_back(Option("features.min_range", "m", "closer returns (vehicle, noise) are dropped",
                     PLUCKER_MEMBER(odometry.features.min_range)));
  t.push_back(Option("features.max_range", "m", "farther returns are dropped",
                     PLUCKER_MEMBER(odometry.features.max_range)));
  t.push_back(Option("features.curvature_half_window", "points",
                     "neighbours on each side along the ring for the curvature",
                     PLUCKER_MEMBER(odometry.features.curvature_half_window)));
  t.push_back(Option("features.sectors", "", "equal-count sectors per ring",
                     PLUCKER_MEMBER(odometry.features.sectors)));
  t.push_back(Option("features.max_sharp_per_sector", "", "strongest edge points per sector",
                     PLUCKER_MEMBER(odometry.features.max_sharp_per_sector)));
  t.push_back(Option("features.max_edges_per_sector", "",
                     "edge points (sharp + less sharp) per sector",
                     PLUCKER_MEMBER(odometry.features.max_edges_per_sector)));
  t.push_back(Option("features.max_flat_per_sector", "", "strongest plane points per sector",
                     PLUCKER_MEMBER(odometry.features.max_flat_per_sector)));
  t.push_back(Option("features.edge_threshold", "m^2", "curvature above: edge candidate",
                     PLUCKER_MEMBER(odometry.features.edge_threshold)));
  t.push_back(Option("features.plane_threshold", "m^2", "curvature below: plane candidate",
                     PLUCKER_MEMBER(odometry.features.plane_threshold)));
  t.push_back(Option("features.suppression_distance", "m",
                     "neighbours closer than this to a pick are suppressed",
                     PLUCKER_MEMBER(odometry.features.suppression_distance)));
  t.push_back(Option("features.occlusion_depth_jump", "",
                     "relative depth jump |d_i - d_j| / min(d) that starts the occlusion test",
                     PLUCKER_MEMBER(odometry.features.occlusion_depth_jump)));
  t.push_back(Option("features.occlusion_max_gap", "m",
                     "the jump counts only between angularly adjacent points (gap at equal depth)",
                     PLUCKER_MEMBER(odometry.features.occlusion_max_gap)));
  t.push_back(Option("features.parallel_beam_ratio", "",
                     "beam-parallel surface: |p_i - p_i+-1|^2 > ratio |p_i|^2 on both sides",
                     PLUCKER_MEMBER(odometry.features.parallel_beam_ratio)));
  t.push_back(Option("features.edge_voxel_size", "m", "downsampling of the edge points (0: off)",
                     PLUCKER_MEMBER(odometry.features.edge_voxel_size)));
  t.push_back(Option("features.plane_voxel_size", "m", "downsampling of the plane points (0: off)",
                     PLUCKER_MEMBER(odometry.features.plane_voxel_size)));
  t.push_back(Option("features.scan_period", "s", "one revolution (point time from azimuth)",
                     PLUCKER_MEMBER(odometry.features.scan_period)));
  // edge_map, plane_map: lidar/voxel_map.h
  t.push_back(Option("edge_map.voxel_size", "m", "voxel edge; also the largest search radius",
                     PLUCKER_MEMBER(odometry.edge_map.voxel_size)));
  t.push_back(Option("edge_map.max_points_per_voxel", "", "points kept per voxel",
                     PLUCKER_MEMBER(odometry.edge_map.max_points_per_voxel)));
  t.push_back(Option("edge_map.min_point_distance", "m",
                     "a new point closer than this to a kept one is skipped",
                     PLUCKER_MEMBER(odometry.edge_map.min_point_distance)));
  t.push_back(Option("edge_map.max_distance", "m",
                     "voxels farther than this from the sensor are dropped",
                     PLUCKER_MEMBER(odometry.edge_map.max_distance)));
  t.push_back(Option("plane_map.voxel_size", "m", "voxel edge; also the largest search radius",
                     PLUCKER_MEMBER(odometry.plane_map.voxel_size)));
  t.push_back(Option("plane_map.max_points_per_voxel", "", "points kept per voxel",
                     PLUCKER_MEMBER(odometry.plane_map.max_points_per_voxel)));
  t.push_back(Option("plane_map.min_point_distance", "m",
                     "a new point closer than this to a kept one is skipped",
                     PLUCKER_MEMBER(odometry.plane_map.min_point_distance)));
  t.push_back(Option("plane_map.max_distance", "m",
                     "voxels farther than this from the sensor are dropped",
                     PLUCKER_MEMBER(odometry.plane_map.max_distance)));
  // registration: lidar/odometry.h
  t.push_back(Option("registration.num_neighbours", "", "nearest map points per correspondence",
                     PLUCKER_MEMBER(odometry.num_neighbours)));
  t.push_back(Option("registration.max_correspondence_distance", "m",
                     "farthest neighbour allowed (<= map voxel size)",
                     PLUCKER_MEMBER(odometry.max_correspondence_distance)));
  t.push_back(Option("registration.edge_eigen_ratio", "",
                     "a line: largest covariance eigenvalue > ratio x the middle one",
                     PLUCKER_MEMBER(odometry.edge_eigen_ratio)));
  t.push_back(Option("registration.plane_max_residual", "m",
                     "a plane: every neighbour within this of the fitted plane",
                     PLUCKER_MEMBER(odometry.plane_max_residual)));
  t.push_back(Option("registration.edge_sigma", "m", "residual scale of edges (view-dependent)",
                     PLUCKER_MEMBER(odometry.edge_sigma)));
  t.push_back(Option("registration.plane_sigma", "m", "residual scale of planes",
                     PLUCKER_MEMBER(odometry.plane_sigma)));
  t.push_back(
      Choice("registration.loss", "robust loss", PLUCKER_MEMBER(odometry.loss),
             std::vector<std::pair<std::string, RobustLoss>>{{"huber", RobustLoss::kHuber},
                                                             {"cauchy", RobustLoss::kCauchy},
                                                             {"none", RobustLoss::kNone}}));
  t.push_back(Option("registration.loss_scale", "sigma", "parameter of the Huber / Cauchy loss",
                     PLUCKER_MEMBER(odometry.loss_scale)));
  t.push_back(Option("registration.use_edges", "", "use edge correspondences",
                     PLUCKER_MEMBER(odometry.use_edges)));
  t.push_back(Option("registration.association_rounds", "", "re-association rounds per scan",
                     PLUCKER_MEMBER(odometry.association_rounds)));
  t.push_back(Option("registration.max_association_rounds", "",
                     "more rounds while the pose still moves by more than the convergence values",
                     PLUCKER_MEMBER(odometry.max_association_rounds)));
  t.push_back(Option("registration.convergence_translation", "m",
                     "a round that moves the pose less has converged",
                     PLUCKER_MEMBER(odometry.convergence_translation)));
  t.push_back(Option("registration.convergence_rotation_deg", "deg",
                     "a round that turns the pose less has converged",
                     PLUCKER_MEMBER(odometry.convergence_rotation_deg)));
  t.push_back(Option("registration.max_iterations", "", "solver iterations per round",
                     PLUCKER_MEMBER(odometry.max_iterations)));
  t.push_back(Option("registration.max_edge_points", "", "edge points used per scan (strided)",
                     PLUCKER_MEMBER(odometry.max_edge_points)));
  t.push_back(Option("registration.max_plane_points", "", "plane points used per scan (strided)",
                     PLUCKER_MEMBER(odometry.max_plane_points)));
  t.push_back(Option("registration.min_correspondences", "",
                     "fewer: the scan keeps the predicted pose",
                     PLUCKER_MEMBER(odometry.min_correspondences)));
  t.push_back(Option("registration.constant_velocity", "",
                     "constant-velocity prediction (else the previous pose)",
                     PLUCKER_MEMBER(odometry.constant_velocity)));
  t.push_back(Option("registration.start_distance", "m",
                     "without a motion prior (second scan, after skips): coarse-to-fine stages "
                     "from this correspondence distance, halved down to the normal one (0: off)",
                     PLUCKER_MEMBER(odometry.start_distance)));
  // degeneracy: lidar/degeneracy.h
  t.push_back(Option("degeneracy.threshold", "",
                     "a translation is degenerate when its eigen-gap ratio is below this",
                     PLUCKER_MEMBER(odometry.degeneracy_threshold)));
  t.push_back(Option("degeneracy.max_normal_alignment", "plane_sigma^2",
                     "and the mean (normal . direction)^2 of its rows is below this",
                     PLUCKER_MEMBER(odometry.degeneracy_max_normal_alignment)));
  t.push_back(Option("degeneracy.rotation_threshold", "",
                     "rotation eigen-gap ratio (0: rotations never flagged)",
                     PLUCKER_MEMBER(odometry.degeneracy_rotation_threshold)));
  t.push_back(Option("degeneracy.max_rotation_information", "m^2/sigma^2",
                     "rotation information per row below which a rotation is flagged",
                     PLUCKER_MEMBER(odometry.degeneracy_max_rotation_information)));
  t.push_back(Option("degeneracy.handle", "", "keep the prediction along degenerate directions",
                     PLUCKER_MEMBER(odometry.handle_degeneracy)));
  // top level
  t.push_back(
      Choice("deskew", "auto: on when the points have a time", PLUCKER_MEMBER(odometry.deskew),
             std::vector<std::pair<std::string, DeskewMode>>{
                 {"auto", DeskewMode::kAuto}, {"on", DeskewMode::kOn}, {"off", DeskewMode::kOff}}));
  t.push_back(Choice(
      "ring_source",
      "auto: the scan's rings, else the firing order; auto_elevation: else the elevation table",
      PLUCKER_MEMBER(odometry.ring_source),
      std::vector<std::pair<std::string, RingSource>>{
          {"auto", RingSource::kAuto},
          {"scan_order", RingSource::kScanOrder},
          {"elevation", RingSource::kElevation},
          {"auto_elevation", RingSource::kAutoElevation}}));
  t.push_back(Choice("sensor",
                     "auto: the model detected where rings come from elevation; a model: its "
                     "elevation table there (ring_source elevation, a PCD without ring), and "
                     "the first scan must fit it; generic: no rings, features from local "
                     "geometry (as --sensor)",
                     PLUCKER_MEMBER(odometry.sensor),
                     std::vector<std::pair<std::string, std::string>>{{"auto", "auto"},
                                                                      {"hdl64", "hdl64"},
                                                                      {"vlp32", "vlp32"},
                                                                      {"vlp16", "vlp16"},
                                                                      {"os1-64", "os1-64"},
                                                                      {"os1-128", "os1-128"},
                                                                      {"generic", "generic"}}));
  // generic: lidar/geometric_features.h (sensor generic)
  t.push_back(Option("generic.voxel_size", "m", "downsampling before the neighbour search",
                     PLUCKER_MEMBER(odometry.generic.voxel_size)));
  t.push_back(Option("generic.neighbours", "points", "k nearest neighbours (5..32)",
                     PLUCKER_MEMBER(odometry.generic.neighbours)));
  t.push_back(Option("generic.max_neighbour_distance", "m", "farthest of the k neighbours",
                     PLUCKER_MEMBER(odometry.generic.max_neighbour_distance)));
  t.push_back(Option("generic.edge_ratio", "", "l1 > ratio * l2: an edge",
                     PLUCKER_MEMBER(odometry.generic.edge_ratio)));
  t.push_back(Option("generic.plane_ratio", "", "l3 < ratio * l2: a plane",
                     PLUCKER_MEMBER(odometry.generic.plane_ratio)));
  t.push_back(Option("generic.plane_max_thickness", "m", "and sqrt(l3) below this",
                     PLUCKER_MEMBER(odometry.generic.plane_max_thickness)));
  t.push_back(Option("map_cleanup_every", "frames", "frames between map cropping",
                     PLUCKER_MEMBER(odometry.map_cleanup_every)));
  // output
  t.push_back(Option("output.map_voxel_size", "m", "downsampling of --map (as --map-voxel)",
                     PLUCKER_MEMBER(map_voxel_size)));
  return t;
}

#undef PLUCKER_MEMBER

// One comment per group of the defaults file.
const char* GroupComment(const std::string& group) {
  if (group == "features") return "lidar/features.h (LOAM-style per-ring selection)";
  if (group == "edge_map") return "lidar/voxel_map.h, the local map of edge points";
  if (group == "plane_map") return "lidar/voxel_map.h, the local map of plane points";
  if (group == "registration") return "scan-to-map registration, lidar/odometry.h";
  if (group == "degeneracy") return "lidar/degeneracy.h";
  if (group == "generic") return "lidar/geometric_features.h (sensor: generic)";
  if (group == "output") return "plucker lidar outputs";
  return "";
}

std::pair<std::string, std::string> SplitKey(const std::string& key) {
  const std::size_t dot = key.find('.');
  if (dot == std::string::npos) return {"", key};
  return {key.substr(0, dot), key.substr(dot + 1)};
}

std::string Comment(const LidarOption& o) {
  std::string c = o.unit.empty() ? o.doc : o.unit + "; " + o.doc;
  if (o.type.find('|') != std::string::npos) c = o.type + "; " + c;
  return c;
}

void Apply(const YAML::Node& node, const std::string& prefix, const std::string& name,
           LidarConfig* config) {
  if (!node.IsMap()) {
    throw std::runtime_error(name + ": " + (prefix.empty() ? "top level" : "key '" + prefix + "'") +
                             " must be a mapping");
  }
  const std::vector<LidarOption>& table = LidarOptionTable();
  for (const auto& kv : node) {
    const std::string key = (prefix.empty() ? "" : prefix + ".") + kv.first.as<std::string>();
    if (kv.second.IsMap()) {
      Apply(kv.second, key, name, config);
      continue;
    }
    const auto it = std::find_if(table.begin(), table.end(),
                                 [&](const LidarOption& o) { return o.key == key; });
    if (it == table.end()) throw std::runtime_error(name + ": unknown key '" + key + "'");
    try {
      it->set(kv.second, config);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(name + ": key '" + key + "': " + e.what());
    }
  }
}

}  // namespace

const std::vector<LidarOption>& LidarOptionTable() {
  static const std::vector<LidarOption> table = MakeTable();
  return table;
}

std::string LidarConfigYaml(const LidarConfig& config) {
  std::ostringstream out;
  out << "# plucker lidar: every option with its default. Generated from the options table\n"
         "# (apps/plucker/lidar_options_table.cc) by `plucker config lidar`; do not edit by hand.\n"
         "# Pass a copy with your changes via `plucker lidar --config FILE.yaml`; keys you leave "
         "out\n"
         "# keep these defaults. Unknown keys and wrong types are errors naming the file and the "
         "key.\n";
  const std::vector<LidarOption>& table = LidarOptionTable();
  std::string group = "-";
  for (std::size_t i = 0; i < table.size(); ++i) {
    const auto [g, name] = SplitKey(table[i].key);
    if (g != group) {
      out << "\n";
      if (!g.empty()) out << g << ":  # " << GroupComment(g) << "\n";
      group = g;
    }
    const std::string indent = g.empty() ? "" : "  ";
    const std::string line = indent + name + ": " + table[i].get(config);
    out << line << std::string(std::max<int>(1, 40 - static_cast<int>(line.size())), ' ') << "# "
        << Comment(table[i]) << "\n";
  }
  return out.str();
}

std::string LidarOptionsMarkdown() {
  std::ostringstream out;
  const LidarConfig defaults;
  out << "| key | type | default | unit | meaning |\n|---|---|---|---|---|\n";
  auto escape = [](std::string text) {  // a '|' would end the table cell
    for (std::size_t p = text.find('|'); p != std::string::npos; p = text.find('|', p + 2))
      text.replace(p, 1, "\\|");
    return text;
  };
  for (const LidarOption& o : LidarOptionTable()) {
    out << "| `" << o.key << "` | " << escape(o.type) << " | `" << o.get(defaults) << "` | "
        << o.unit << " | " << escape(o.doc) << " |\n";
  }
  return out.str();
}

void ApplyLidarConfigYaml(const std::string& text, const std::string& name, LidarConfig* config) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(name + ": invalid YAML: " + e.msg);
  }
  if (root.IsNull()) return;  // an empty file keeps the defaults
  Apply(root, "", name, config);
}

void LoadLidarConfig(const std::string& path, LidarConfig* config) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw std::runtime_error(path + ": cannot open");
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(path + ": invalid YAML: " + e.msg);
  }
  if (root.IsNull()) return;
  Apply(root, "", path, config);
}

}  // namespace app
}  // namespace plucker
