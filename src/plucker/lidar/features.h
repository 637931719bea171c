// LOAM-style feature extraction from one LiDAR scan (Zhang and Singh, "LOAM: Lidar Odometry and
// Mapping in Real-time", RSS 2014), written for this project.
//
// Per ring, points in firing order: 1. range gating (finite, min_range..max_range); 2. curvature
// c_i = |sum_{j=-k..k, j!=0} (p_{i+j} - p_i)|^2 (m^2), k = curvature_half_window; 3. LOAM's
// rejections: the k points on the far side of a depth jump (possibly occluded) and points on
// surfaces nearly parallel to the beam; 4. per `sectors` equal parts of a ring, the largest
// curvatures above edge_threshold become `edges` (the strongest also `sharp`), the smallest below
// plane_threshold `flat`, each pick suppressing its +-k neighbours (closer than
// suppression_distance); 5. `planes` = every remaining low-curvature point; edges and planes are
// voxel-downsampled. Per-point time: the scan's time channel, else from the azimuth swept since
// the ring's first point (fraction of a revolution times scan_period).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "plucker/sensor/lidar_scan.h"

namespace plucker {
namespace lidar {

struct FeatureOptions {
  double min_range = 2.0;              // m; closer returns (vehicle, noise) are dropped
  double max_range = 100.0;            // m
  int curvature_half_window = 5;       // k: neighbours on each side along the ring
  int sectors = 6;                     // equal-count sectors per ring
  int max_sharp_per_sector = 2;        // strongest edge points per sector
  int max_edges_per_sector = 20;       // edge points (sharp + less sharp) per sector
  int max_flat_per_sector = 4;         // strongest plane points per sector
  double edge_threshold = 0.1;         // m^2; curvature above -> edge candidate
  double plane_threshold = 0.1;        // m^2; curvature below -> plane candidate
  double suppression_distance = 0.25;  // m; neighbours closer than this to a pick are suppressed
  double occlusion_depth_jump = 0.1;   // relative depth jump |d_i - d_j| / min(d) => occlusion test
  double occlusion_max_gap = 0.3;  // m; the jump only counts if the points are angularly adjacent
                                   // (their distance after scaling to the same depth is below)
  double parallel_beam_ratio = 0.0002;  // LOAM: |p_i - p_{i+-1}|^2 > ratio * |p_i|^2 on both sides
  double edge_voxel_size = 0.2;         // m; downsampling of `edges` (0 = off)
  double plane_voxel_size = 0.4;        // m; downsampling of `planes` (0 = off)
  double scan_period = 0.1;             // s; one revolution (for time from azimuth)
  bool compute_times = false;           // fill the *_times vectors (needed by deskew)
  int num_threads = 1;                  // > 1: rings processed in parallel (same result)
};

struct FeatureStats {
  int input_points = 0;
  int valid_points = 0;  // after range gating and NaN removal
  int rings = 0;         // rings with enough points
  int occluded_rejected = 0;
  int parallel_rejected = 0;
  int sharp = 0, edges = 0, flat = 0, planes = 0;
  bool times_from_azimuth = false;
};

struct ScanFeatures {
  std::vector<Eigen::Vector3d> sharp;   // strongest edge points (subset of the edge picks)
  std::vector<Eigen::Vector3d> edges;   // all edge points (sharp + less sharp), downsampled
  std::vector<Eigen::Vector3d> flat;    // strongest plane points
  std::vector<Eigen::Vector3d> planes;  // flat + less flat, downsampled
  std::vector<double> edge_times;       // seconds from scan start, one per `edges` (if computed)
  std::vector<double> plane_times;      // one per `planes` (if computed)
  FeatureStats stats;
};

// Extracts the features of a stream of scans, keeping its working buffers from one scan to the
// next (no megabytes allocated and freed per scan). `scan.ring` must be filled (0..N-1, -1 =
// unassigned; sensor/lidar_model.h assigns rings) and a ring's points must be in firing order.
// Extract returns false with `*error` set when the scan is unusable (no rings, mismatched channel
// sizes, fewer than 2k+1 valid points on every ring); non-finite points are skipped (counted as
// invalid). The vectors of `*features` are refilled in place (their capacity reused).
class FeatureExtractor {
 public:
  FeatureExtractor();
  ~FeatureExtractor();

  bool Extract(const LidarScan& scan, const FeatureOptions& options, ScanFeatures* features,
               std::string* error);

 private:
  struct Buffers;
  std::unique_ptr<Buffers> buffers_;
};

// Keeps one point per cubic voxel of side `voxel_size` (the first seen), preserving order. The
// optional `times` vector is filtered alongside. voxel_size <= 0 leaves the input unchanged.
void VoxelDownsample(double voxel_size, std::vector<Eigen::Vector3d>* points,
                     std::vector<double>* times = nullptr);

}  // namespace lidar
}  // namespace plucker
