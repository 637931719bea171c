#include "lidar_options_table.h"

namespace plucker {
namespace app {
namespace {

using factors::RobustLoss;
using lidar::DeskewMode;
using lidar::RingSource;

std::vector<LidarOption> MakeRows() {
  OptionRows<LidarConfig> t;
  t.Value("features.min_range", "m", "closer returns (vehicle, noise) are dropped", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(odometry.features.min_range));
  t.Value("features.max_range", "m", "farther returns are dropped", Above(0.0),
          PLUCKER_OPTION_MEMBER(odometry.features.max_range));
  t.Value("features.curvature_half_window", "points",
          "neighbours on each side along the ring for the curvature", Between(1, 50),
          PLUCKER_OPTION_MEMBER(odometry.features.curvature_half_window));
  t.Value("features.sectors", "", "equal-count sectors per ring", Between(1, 1000),
          PLUCKER_OPTION_MEMBER(odometry.features.sectors));
  t.Value("features.max_sharp_per_sector", "", "strongest edge points per sector", AtLeast(0),
          PLUCKER_OPTION_MEMBER(odometry.features.max_sharp_per_sector));
  t.Value("features.max_edges_per_sector", "", "edge points (sharp + less sharp) per sector",
          AtLeast(0), PLUCKER_OPTION_MEMBER(odometry.features.max_edges_per_sector));
  t.Value("features.max_flat_per_sector", "", "strongest plane points per sector", AtLeast(0),
          PLUCKER_OPTION_MEMBER(odometry.features.max_flat_per_sector));
  t.Value("features.edge_threshold", "m^2", "curvature above: edge candidate", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(odometry.features.edge_threshold));
  t.Value("features.plane_threshold", "m^2", "curvature below: plane candidate", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(odometry.features.plane_threshold));
  t.Value("features.suppression_distance", "m",
          "neighbours closer than this to a pick are suppressed", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(odometry.features.suppression_distance));
  t.Value("features.occlusion_depth_jump", "",
          "relative depth jump |d_i - d_j| / min(d) that starts the occlusion test", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(odometry.features.occlusion_depth_jump));
  t.Value("features.occlusion_max_gap", "m",
          "the jump counts only between angularly adjacent points (gap at equal depth)",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(odometry.features.occlusion_max_gap));
  t.Value("features.parallel_beam_ratio", "",
          "beam-parallel surface: |p_i - p_i+-1|^2 > ratio |p_i|^2 on both sides", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(odometry.features.parallel_beam_ratio));
  t.Value("features.edge_voxel_size", "m", "downsampling of the edge points (0: off)", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(odometry.features.edge_voxel_size));
  t.Value("features.plane_voxel_size", "m", "downsampling of the plane points (0: off)",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(odometry.features.plane_voxel_size));
  t.Value("features.scan_period", "s", "one revolution (point time from azimuth)", Above(0.0),
          PLUCKER_OPTION_MEMBER(odometry.features.scan_period));
  t.Value("edge_map.voxel_size", "m", "voxel edge; also the largest search radius", Above(0.0),
          PLUCKER_OPTION_MEMBER(odometry.edge_map.voxel_size));
  t.Value("edge_map.max_points_per_voxel", "", "points kept per voxel", Between(1, 10000),
          PLUCKER_OPTION_MEMBER(odometry.edge_map.max_points_per_voxel));
  t.Value("edge_map.min_point_distance", "m",
          "a new point closer than this to a kept one is skipped", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(odometry.edge_map.min_point_distance));
  t.Value("edge_map.max_distance", "m", "voxels farther than this from the sensor are dropped",
          Above(0.0), PLUCKER_OPTION_MEMBER(odometry.edge_map.max_distance));
  t.Value("plane_map.voxel_size", "m", "voxel edge; also the largest search radius", Above(0.0),
          PLUCKER_OPTION_MEMBER(odometry.plane_map.voxel_size));
  t.Value("plane_map.max_points_per_voxel", "", "points kept per voxel", Between(1, 10000),
          PLUCKER_OPTION_MEMBER(odometry.plane_map.max_points_per_voxel));
  t.Value("plane_map.min_point_distance", "m",
          "a new point closer than this to a kept one is skipped", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(odometry.plane_map.min_point_distance));
  t.Value("plane_map.max_distance", "m", "voxels farther than this from the sensor are dropped",
          Above(0.0), PLUCKER_OPTION_MEMBER(odometry.plane_map.max_distance));
  t.Value("registration.num_neighbours", "", "nearest map points per correspondence",
          Between(3, 16), PLUCKER_OPTION_MEMBER(odometry.num_neighbours));
  t.Value("registration.max_correspondence_distance", "m",
          "farthest neighbour allowed (<= map voxel size)", Above(0.0),
          PLUCKER_OPTION_MEMBER(odometry.max_correspondence_distance));
  t.Value("registration.edge_eigen_ratio", "",
          "a line: largest covariance eigenvalue > ratio x the middle one", AtLeast(1.0),
          PLUCKER_OPTION_MEMBER(odometry.edge_eigen_ratio));
  t.Value("registration.plane_max_residual", "m",
          "a plane: every neighbour within this of the fitted plane", Above(0.0),
          PLUCKER_OPTION_MEMBER(odometry.plane_max_residual));
  t.Value("registration.edge_sigma", "m", "residual scale of edges (view-dependent)", Above(0.0),
          PLUCKER_OPTION_MEMBER(odometry.edge_sigma));
  t.Value("registration.plane_sigma", "m", "residual scale of planes", Above(0.0),
          PLUCKER_OPTION_MEMBER(odometry.plane_sigma));
  t.Choice("registration.loss", "robust loss", PLUCKER_OPTION_MEMBER(odometry.loss),
           std::vector<std::pair<std::string, RobustLoss>>{{"huber", RobustLoss::kHuber},
                                                           {"cauchy", RobustLoss::kCauchy},
                                                           {"none", RobustLoss::kNone}});
  t.Value("registration.loss_scale", "sigma", "parameter of the Huber / Cauchy loss", Above(0.0),
          PLUCKER_OPTION_MEMBER(odometry.loss_scale));
  t.Bool("registration.use_edges", "use edge correspondences",
         PLUCKER_OPTION_MEMBER(odometry.use_edges));
  t.Value("registration.association_rounds", "", "re-association rounds per scan", Between(1, 100),
          PLUCKER_OPTION_MEMBER(odometry.association_rounds));
  t.Value("registration.max_association_rounds", "",
          "more rounds while the pose still moves by more than the convergence values",
          Between(1, 100), PLUCKER_OPTION_MEMBER(odometry.max_association_rounds));
  t.Value("registration.convergence_translation", "m",
          "a round that moves the pose less has converged", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(odometry.convergence_translation));
  t.Value("registration.convergence_rotation_deg", "deg",
          "a round that turns the pose less has converged", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(odometry.convergence_rotation_deg));
  t.Value("registration.max_iterations", "", "solver iterations per round", Between(1, 1000),
          PLUCKER_OPTION_MEMBER(odometry.max_iterations));
  t.Value("registration.max_edge_points", "", "edge points used per scan (strided)", AtLeast(0),
          PLUCKER_OPTION_MEMBER(odometry.max_edge_points));
  t.Value("registration.max_plane_points", "", "plane points used per scan (strided)", AtLeast(1),
          PLUCKER_OPTION_MEMBER(odometry.max_plane_points));
  t.Value("registration.min_correspondences", "", "fewer: the scan keeps the predicted pose",
          AtLeast(0), PLUCKER_OPTION_MEMBER(odometry.min_correspondences));
  t.Bool("registration.constant_velocity", "constant-velocity prediction (else the previous pose)",
         PLUCKER_OPTION_MEMBER(odometry.constant_velocity));
  t.Value("registration.start_distance", "m",
          "without a motion prior (second scan, after skips): coarse-to-fine stages "
          "from this correspondence distance, halved down to the normal one (0: off)",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(odometry.start_distance));
  t.Value("registration.start_max_speed", "m/s",
          "a gap right after the first scan: the start path from forward offsets up to this "
          "speed times the time elapsed; of the candidates within 10 % of the most matches the "
          "lowest cost per match is kept, unless another's weakest translation information is "
          "3x its (0: off)",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(odometry.start_max_speed));
  t.Bool("registration.restart_from_stamps",
         "a scan more than 1.5 intervals after the last: the velocity step once per interval "
         "elapsed, then the start path",
         PLUCKER_OPTION_MEMBER(odometry.restart_from_stamps));
  t.Value("registration.restart_min_plane_match", "",
          "fewer plane points matched (fraction): registered again through the start path (0: "
          "never)",
          Between(0.0, 1.0), PLUCKER_OPTION_MEMBER(odometry.restart_min_plane_match));
  t.Value("degeneracy.threshold", "",
          "a translation is degenerate when its eigen-gap ratio is below this", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(odometry.degeneracy_threshold));
  t.Value("degeneracy.max_normal_alignment", "plane_sigma^2",
          "and the mean (normal . direction)^2 of its rows is below this", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(odometry.degeneracy_max_normal_alignment));
  t.Value("degeneracy.rotation_threshold", "",
          "rotation eigen-gap ratio (0: rotations never flagged)", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(odometry.degeneracy_rotation_threshold));
  t.Value("degeneracy.max_rotation_information", "m^2/sigma^2",
          "rotation information per row below which a rotation is flagged", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(odometry.degeneracy_max_rotation_information));
  t.Bool("degeneracy.handle", "keep the prediction along degenerate directions",
         PLUCKER_OPTION_MEMBER(odometry.handle_degeneracy));
  t.Choice("deskew", "auto: on when the points have a time", PLUCKER_OPTION_MEMBER(odometry.deskew),
           std::vector<std::pair<std::string, DeskewMode>>{
               {"auto", DeskewMode::kAuto}, {"on", DeskewMode::kOn}, {"off", DeskewMode::kOff}});
  t.Choice(
      "ring_source",
      "auto: the scan's rings, else the firing order; auto_elevation: else the elevation table",
      PLUCKER_OPTION_MEMBER(odometry.ring_source),
      std::vector<std::pair<std::string, RingSource>>{
          {"auto", RingSource::kAuto},
          {"scan_order", RingSource::kScanOrder},
          {"elevation", RingSource::kElevation},
          {"auto_elevation", RingSource::kAutoElevation}});
  t.Choice("sensor",
           "auto: the model detected where rings come from elevation; a model: its elevation "
           "table there (ring_source elevation, a PCD without ring), and the first scan must fit "
           "it; generic: no rings, features from local geometry (as --sensor)",
           PLUCKER_OPTION_MEMBER(odometry.sensor),
           std::vector<std::pair<std::string, std::string>>{{"auto", "auto"},
                                                            {"hdl64", "hdl64"},
                                                            {"vlp32", "vlp32"},
                                                            {"vlp16", "vlp16"},
                                                            {"os1-64", "os1-64"},
                                                            {"os1-128", "os1-128"},
                                                            {"generic", "generic"}});
  // generic: lidar/geometric_features.h (sensor generic)
  t.Value("generic.voxel_size", "m", "downsampling before the neighbour search", Above(0.0),
          PLUCKER_OPTION_MEMBER(odometry.generic.voxel_size));
  t.Value("generic.neighbours", "points", "k nearest neighbours", Between(5, 32),
          PLUCKER_OPTION_MEMBER(odometry.generic.neighbours));
  t.Value("generic.max_neighbour_distance", "m", "farthest of the k neighbours", Above(0.0),
          PLUCKER_OPTION_MEMBER(odometry.generic.max_neighbour_distance));
  t.Value("generic.edge_ratio", "", "l1 > ratio * l2: an edge", AtLeast(1.0),
          PLUCKER_OPTION_MEMBER(odometry.generic.edge_ratio));
  t.Value("generic.plane_ratio", "", "l3 < ratio * l2: a plane", Between(0.0, 1.0),
          PLUCKER_OPTION_MEMBER(odometry.generic.plane_ratio));
  t.Value("generic.plane_max_thickness", "m", "and sqrt(l3) below this", Above(0.0),
          PLUCKER_OPTION_MEMBER(odometry.generic.plane_max_thickness));
  t.Value("map_cleanup_every", "frames", "frames between map cropping", Between(1, 1000000),
          PLUCKER_OPTION_MEMBER(odometry.map_cleanup_every));
  t.Value("output.map_voxel_size", "m", "downsampling of --map (as --map-voxel)", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(map_voxel_size));
  return t.Take();
}

}  // namespace

const LidarOptionsTable& LidarOptions() {
  static const LidarOptionsTable table(
      TableText{"lidar",
                "apps/plucker/lidar_options_table.cc",
                {{"features", "lidar/features.h (LOAM-style per-ring selection)"},
                 {"edge_map", "lidar/voxel_map.h, the local map of edge points"},
                 {"plane_map", "lidar/voxel_map.h, the local map of plane points"},
                 {"registration", "scan-to-map registration, lidar/odometry.h"},
                 {"degeneracy", "lidar/degeneracy.h"},
                 {"generic", "lidar/geometric_features.h (sensor: generic)"},
                 {"output", "plucker lidar outputs"}},
                {}},
      MakeRows());
  return table;
}

const std::vector<LidarOption>& LidarOptionTable() { return LidarOptions().rows(); }

std::string LidarConfigYaml(const LidarConfig& config) { return LidarOptions().Yaml(config); }

std::string LidarOptionsMarkdown() { return LidarOptions().Markdown(LidarConfig()); }

void ApplyLidarConfigYaml(const std::string& text, const std::string& name, LidarConfig* config) {
  LidarOptions().Apply(text, name, config);
}

void LoadLidarConfig(const std::string& path, LidarConfig* config) {
  LidarOptions().Load(path, config);
}

}  // namespace app
}  // namespace plucker
