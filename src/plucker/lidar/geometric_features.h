// Features of a cloud without rings and without a spinning order (Livox-like; `--sensor
// generic`): from the local geometry of a voxel-downsampled cloud instead of LOAM's curvature
// along a ring. Per point of the downsampled cloud, the covariance of its k nearest neighbours
// (nanoflann KD-tree), eigenvalues l1 >= l2 >= l3:
//   edge  (one dominant eigenvector): l1 > edge_ratio * l2;
//   else plane (one small eigenvalue): l3 < plane_ratio * l2 and the normal spread
//                                     sqrt(l3) below plane_max_thickness;
// neighbourhoods whose farthest neighbour lies beyond max_neighbour_distance (sparse, far) give
// nothing. Per-point time is the scan's time channel when it has one (there is no spinning order
// to derive it from).
#pragma once

#include <memory>
#include <string>

#include "plucker/geometry/se3.h"
#include "plucker/lidar/features.h"
#include "plucker/sensor/lidar_scan.h"

namespace plucker {
namespace lidar {

struct GeometricFeatureOptions {
  double voxel_size = 0.2;              // m; downsampling before the neighbour search
  int neighbours = 10;                  // k (>= 5, <= 32)
  double max_neighbour_distance = 1.5;  // m; farthest of the k neighbours
  double edge_ratio = 5.0;              // l1 > ratio * l2 -> edge
  double plane_ratio = 0.05;            // l3 < ratio * l2 -> plane
  double plane_max_thickness = 0.08;    // m; sqrt(l3) below this for a plane
};

// Fills features->edges / planes (sharp = edges, flat = planes) and, with
// `ring_options.compute_times` and a time channel, the times. Range gating (min_range,
// max_range) and the voxel sizes of `edges` / `planes` come from `ring_options` (FeatureOptions).
// Returns false with *error set for an unusable scan (mismatched channel sizes, fewer than
// `neighbours` valid points). With `plane_information`, also the information of the plane points
// as point-to-plane rows at the identity pose, sum of J^T J with J = [(p x n)^T, n^T] (tangent
// (dtheta, dt) as in degeneracy.h; n the fitted normal), over the plane points before their
// downsampling to plane_voxel_size: how well the planes of this cloud constrain each direction.
class GeometricFeatureExtractor {
 public:
  GeometricFeatureExtractor();
  ~GeometricFeatureExtractor();
  bool Extract(const LidarScan& scan, const FeatureOptions& ring_options,
               const GeometricFeatureOptions& options, ScanFeatures* features, std::string* error,
               Matrix6d* plane_information = nullptr);

 private:
  struct Buffers;
  std::unique_ptr<Buffers> buffers_;
};

}  // namespace lidar
}  // namespace plucker
