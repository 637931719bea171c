// LOAM-style LiDAR odometry: features (lidar/features.h), scan-to-map registration against a
// bounded voxel map with the analytic point-to-edge/plane factors (factors/lidar_factors.h), a
// robust loss and degeneracy handling (lidar/degeneracy.h). No file I/O, no clocks: the caller
// times the stages through an optional StageObserver. ProcessScan, after rings and features:
//   1. predict: T_w_s_pred = T_w_s_prev T_s_prev2_s_prev (constant velocity, PredictPose);
//   2. deskew (scans with per-point time) with the sweep motion T_w_s_prev^-1 T_w_s;
//   3. register, association_rounds times (up to max_association_rounds while the pose moves
//      more than the convergence thresholds): re-deskew, correspond (nearest map points: an
//      edge if their covariance is elongated, a plane if all lie within plane_max_residual of
//      it), solve (lidar/pose_solver.h), remap along degenerate directions;
//   4. update the map (UpdateLocalMap), dropping far voxels every map_cleanup_every frames. When
//      deskewing, the first scan seeds the map raw; after the second both are deskewed and the
//      map rebuilt (odometry.cc: RebuildMapFromSeed).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "plucker/factors/robust_loss.h"
#include "plucker/geometry/se3.h"
#include "plucker/lidar/degeneracy.h"
#include "plucker/lidar/features.h"
#include "plucker/lidar/geometric_features.h"
#include "plucker/lidar/voxel_map.h"
#include "plucker/sensor/lidar_scan.h"

namespace plucker {
namespace lidar {

enum class RingSource {
  kAuto,       // the scan's ring field; if absent, from the firing order (KITTI .bin)
  kScanOrder,  // always from the firing order
  kElevation,  // from the elevation table of `sensor` (auto-detected on the first scan if "auto")
  kAutoElevation,  // the scan's ring field; if absent, from the elevation table (PCD without ring)
};

enum class DeskewMode { kAuto, kOn, kOff };  // kAuto: on when the scan has per-point time

struct LidarOdometryOptions {
  FeatureOptions features;
  RingSource ring_source = RingSource::kAuto;
  // hdl64 | vlp32 | vlp16 | os1-64 | os1-128 (the elevation table of kElevation) | auto (detected
  // for kElevation) | generic: no rings, no spinning order (Livox-like): ring_source is ignored,
  // features come from local geometry (`generic`, geometric_features.h) and deskewing needs the
  // scan's per-point time (there is no azimuth order to derive it from).
  std::string sensor = "auto";
  GeometricFeatureOptions generic;
  DeskewMode deskew = DeskewMode::kAuto;

  VoxelMapOptions edge_map{1.0, 10, 0.2, 100.0};  // voxel, cap, spacing, radius
  VoxelMapOptions plane_map{1.0, 20, 0.3, 100.0};
  int num_neighbours = 5;                    // KNN for each correspondence (<= 16)
  double max_correspondence_distance = 1.0;  // m; farthest neighbour allowed (<= voxel size)
  double edge_eigen_ratio = 3.0;             // lambda_max > ratio * lambda_mid for a line
  double plane_max_residual = 0.05;          // m; every neighbour within this of the plane
  double edge_sigma = 0.5;                   // m; residual scale of edges (view-dependent)
  double plane_sigma = 0.05;                 // m; residual scale of planes
  factors::RobustLoss loss = factors::RobustLoss::kHuber;
  double loss_scale = 2.0;  // in sigma units (Huber/Cauchy parameter)
  bool use_edges = true;
  int association_rounds = 2;              // re-association rounds per scan (minimum)
  int max_association_rounds = 5;          // more rounds while the pose still moves by more
  double convergence_translation = 0.005;  // m   than these in a round (large initial errors,
  double convergence_rotation_deg = 0.02;  // deg e.g. the first scan pair from zero velocity)
  int max_iterations = 4;                  // solver iterations per round
  int max_edge_points = 1000;              // cap on edge points used per scan (stride sampling)
  int max_plane_points = 3000;             // cap on plane points used per scan
  int min_correspondences = 30;            // fewer -> the scan keeps the predicted pose
  // Degeneracy (degeneracy.h, docs/math/lidar-odometry.md). Rotation flags are off by default
  // (they flagged well-determined yaw in the simulated streets). Translation ceiling: the mean
  // squared normal component along the direction, (3.3 deg)^2, used / plane_sigma^2.
  double degeneracy_threshold = 0.03;  // translation eigen-gap ratio
  double degeneracy_max_normal_alignment = 0.00325;
  double degeneracy_rotation_threshold = 0.0;          // rotation eigen-gap ratio (0: off)
  double degeneracy_max_rotation_information = 1e300;  // m^2/sigma^2 per row
  bool handle_degeneracy = true;  // remap the solution along degenerate directions
  bool constant_velocity = true;  // else the prediction is the previous pose
  // Start without a motion prior (the second scan, and every scan whose prediction does not rest
  // on two registered poses, e.g. after skipped scans): coarse-to-fine stages run before the
  // normal registration, against maps of voxel size d re-sampled from the local map, for
  // d = start_distance, start_distance / 2, ... while d > max_correspondence_distance; plane and
  // edge sigmas, the plane test and the convergence values scale with d (odometry.cc,
  // StartStageOptions). 0: off.
  double start_distance = 4.0;  // m
  // A gap right after the first scan (skipped or absent scans before any motion is known): the
  // start path runs from forward offsets along the sensor's x axis (a vehicle-mounted sensor)
  // every start_distance / 2 up to start_max_speed times the time since the first scan (the
  // scan times, else scan_period per frame slot), and keeps the best by its normal registration
  // (matches, cost per match, information along its weakest translation: odometry_start.cc);
  // the next scan is predicted with the gap's motion per period. 0: off (the start path from
  // the first pose).
  double start_max_speed = 35.0;  // m/s
  // Restart after a gap (scans missing without a skipped frame, seen from the scan timestamps):
  // when a scan comes more than 1.5 scan intervals after the last one, the constant-velocity
  // step is applied once per interval elapsed and the scan takes the start path (with
  // restart_from_stamps; PredictPoseAt). And a scan
  // whose normal registration matches fewer than this fraction of its plane points (the scans
  // of the KITTI extracts match 0.48-0.63) is registered again through the start path from the
  // prediction (0: never).
  bool restart_from_stamps = true;
  double restart_min_plane_match = 0.25;
  int map_cleanup_every = 10;  // frames between RemoveFar calls
  int num_threads = 1;         // threads (TBB) for features and correspondences
};

struct FrameResult {
  bool ok = false;    // false: the pose is the prediction (see `error`)
  std::string error;  // why the frame was not registered
  SE3d T_w_s;         // scan pose (frame 0 = identity)
  FeatureStats features;
  int edge_points = 0, plane_points = 0;                    // features used
  int edge_correspondences = 0, plane_correspondences = 0;  // of the last round
  int association_rounds = 0;                               // rounds run
  bool restarted = false;     // a poor fit from the prediction was redone by the start path
  int start_rounds = 0;       // rounds of the coarse start stages (start_distance), 0 when none ran
  int solver_iterations = 0;  // solver iterations over all rounds
  double final_cost = 0.0;
  DegeneracyInfo degeneracy;
  bool deskewed = false;
  bool map_rebuilt = false;  // the seed scan, now deskewable, replaced its raw points in the map
  std::size_t map_points = 0;
};

// The stages of ProcessScan, in order; kDone ends a frame.
enum class Stage { kRings, kFeatures, kCorrespondences, kSolve, kMapUpdate, kDone };
constexpr int kNumStages = 5;  // before kDone
// Called when a stage begins (correspondences and solve alternate over the association rounds),
// and with kDone at the end of every frame: the caller reads its own clock there.
using StageObserver = std::function<void(Stage)>;

class LidarOdometry {
 public:
  explicit LidarOdometry(const LidarOdometryOptions& options = LidarOdometryOptions());
  ~LidarOdometry();

  // Registers one scan; the copy is needed when rings must be assigned (use the rvalue overload
  // to avoid it).
  FrameResult ProcessScan(const LidarScan& scan, const StageObserver& observer = nullptr);
  FrameResult ProcessScan(LidarScan&& scan, const StageObserver& observer = nullptr);
  // Records a frame that could not be read: its pose is the constant-velocity prediction (at
  // `stamp`, the frame's time in seconds, when known: see PredictPose).
  FrameResult SkipFrame(const std::string& reason, double stamp = 0.0);

  const std::vector<SE3d>& poses() const { return poses_; }
  const VoxelMap& edge_map() const { return edge_map_; }
  const VoxelMap& plane_map() const { return plane_map_; }
  const LidarOdometryOptions& options() const { return options_; }

 private:
  class Impl;
  // The steps of ProcessScan (odometry.cc).
  void AssignScanRings(LidarScan* scan);
  void RegisterToMap(const SE3d& T_w_s_pred, bool deskew, const StageObserver& observer,
                     ScanFeatures* features, FrameResult* result);
  SE3d RegisterStart(const StageObserver& observer, ScanFeatures* features, FrameResult* result);
  SE3d RegisterWideStart(double periods, const StageObserver& observer, ScanFeatures* features,
                         FrameResult* result);
  double PeriodsSinceSeed() const;
  bool PredictAfterWideStart(double stamp, SE3d* T_w_s_pred);
  bool RunRounds(const LidarOdometryOptions& o, const VoxelMap& edge_map, const VoxelMap& plane_map,
                 const SE3d& T_w_s_anchor, bool deskew_first_round, const StageObserver& observer,
                 ScanFeatures* features, FrameResult* result);
  void DeskewFeatures(const SE3d& T_w_s, ScanFeatures* features) const;
  bool SolveRound(const LidarOdometryOptions& o, const SE3d& T_w_s_anchor, FrameResult* result);
  void UpdateMap(bool deskew, ScanFeatures* features, FrameResult* result);
  void RebuildMapFromSeed(const SE3d& T_w_s, ScanFeatures* features);
  LidarOdometryOptions options_;
  VoxelMap edge_map_, plane_map_;
  std::vector<SE3d> poses_;     // one per processed or skipped frame
  std::vector<double> stamps_;  // their times (s; LidarScan::timestamp, 0 when unknown)
  // The last pose came from the wide start over this many periods (0: not) from T_w_s_wide_from_.
  double wide_start_periods_ = 0.0;
  SE3d T_w_s_wide_from_;
  std::unique_ptr<Impl> impl_;
};

// Step 1, prediction from the poses so far: T_w_s_prev T_s_prev2_s_prev (constant velocity), the
// previous pose when constant_velocity is off or only one pose exists, identity for none.
SE3d PredictPose(const std::vector<SE3d>& T_w_s, bool constant_velocity);
// The same at time `stamp` given the poses' times: the last motion T_s_prev2_s_prev spans m
// scan periods (m = round((t_prev - t_prev2) / (stamp - t_prev)) when that is 2 or more, e.g. the
// first scan after a gap, else 1); its m-th root (rotation angle and translation / m) is applied
// n times, n = round((stamp - t_prev) / period) when that is 2 or more (a gap of n - 1 scans
// never given, e.g. deleted files), else once; *steps = n. Unknown (0) or non-increasing times,
// or m = n = 1, give PredictPose.
SE3d PredictPoseAt(const std::vector<SE3d>& T_w_s, const std::vector<double>& stamps, double stamp,
                   bool constant_velocity, int* steps);

// The options of the coarse start stage at correspondence distance d (LidarOdometryOptions::
// start_distance): maps of voxel size d, the map spacing, sigmas, plane test and convergence
// values scaled by d / max_correspondence_distance.
LidarOdometryOptions StartStageOptions(const LidarOdometryOptions& o, double d);

// Step 4, map update: a scan's feature points, given in the sensor frame and moved in place to
// the world frame with T_w_s, enter the maps; with remove_far, voxels farther than their map's
// max_distance from the sensor are then dropped.
void UpdateLocalMap(const SE3d& T_w_s, bool remove_far, std::vector<Eigen::Vector3d>* edges,
                    std::vector<Eigen::Vector3d>* planes, VoxelMap* edge_map, VoxelMap* plane_map);

}  // namespace lidar
}  // namespace plucker
