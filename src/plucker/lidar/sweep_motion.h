// Features of a sweep without a spinning order (sensor generic) with per-point time. Such a
// sensor samples every direction all through the sweep, so at 10 m/s a wall across the road
// shows up as a 1 m thick slab: no plane, and the along-track motion is unobservable (measured:
// every frame degenerate along x and the estimate stuck at zero motion). The cloud is therefore
// deskewed with the sweep motion before the features are taken, and the features moved back to
// their measured positions (the odometry deskews them again with its own estimate):
//   - the motion is that of the last two poses (constant velocity);
//   - without two poses (the first two scans), a forward translation along the sensor's x axis
//     (a vehicle-mounted sensor) and a yaw, found by search: the candidate that yields the most
//     plane points (coordinate descent on a grid, then a finer one; ~40 extractions, twice).
// Measured (lidar_odometry_sensor_test, 12 sweeps through the first corner of the street grid):
// mean relative error 1.7 cm at 10 m/s, 1.0 cm at 10 +- 2 m/s (3.1 m/s^2); without the search
// 1.1 m (the start never finds the motion); at 10 +- 4 m/s (6.3 m/s^2) the start fails (1.25 m)
// with it too.
#pragma once

#include <string>
#include <vector>

#include "plucker/geometry/se3.h"
#include "plucker/lidar/geometric_features.h"

namespace plucker {
namespace lidar {

struct SweepMotionSearch {
  double max_forward = 3.0;   // m per sweep (30 m/s at 10 Hz): grid of 13 values from 0
  double coarse_step = 0.25;  // m; the fine grid: quarters of it around the best
  double max_yaw_deg = 12.0;  // per sweep: grid of 9 values over +-max_yaw
  double yaw_step_deg = 3.0;  // the fine grid: quarters of it
};

class SweepFeatureExtractor {
 public:
  // Features of `scan` (with a time channel) extracted after deskewing with T_start_end, moved
  // back to their measured positions. False with *error as GeometricFeatureExtractor.
  bool Extract(const LidarScan& scan, const SE3d& T_start_end, const FeatureOptions& ring_options,
               const GeometricFeatureOptions& options, ScanFeatures* features, std::string* error);
  // The forward motion and yaw per sweep (SweepMotionSearch) that give the most plane points.
  SE3d SearchForwardMotion(const LidarScan& scan, const FeatureOptions& ring_options,
                           const GeometricFeatureOptions& options,
                           const SweepMotionSearch& search = SweepMotionSearch());

 private:
  GeometricFeatureExtractor extractor_;
  LidarScan deskewed_;
};

}  // namespace lidar
}  // namespace plucker
