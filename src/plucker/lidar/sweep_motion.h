// Features of a sweep without a spinning order (sensor generic) with per-point time. Such a
// sensor samples every direction all through the sweep, so at 10 m/s a wall across the road
// shows up as a 1 m thick slab: no plane, and the along-track motion is unobservable (measured:
// every frame degenerate along x and the estimate stuck at zero motion). The cloud is therefore
// deskewed with the sweep motion before the features are taken, and the features moved back to
// their measured positions (the odometry deskews them again with its own estimate):
//   - the motion is that of the last two poses (constant velocity);
//   - without two poses (the first two scans), a forward translation along the sensor's x axis
//     (a vehicle-mounted sensor) and a yaw, found by search over the plane information of the
//     deskewed cloud (GeometricFeatureExtractor, point-to-plane rows at the identity): the yaw
//     with the most rotation information about z (a wrong yaw smears the far walls), then the
//     forward motion with the most translation information along x (the walls across the road
//     become planes only at the right forward motion); coordinate descent on a grid, then a
//     finer one (~52 extractions). The first scan then seeds the map deskewed with its motion
//     (odometry.cc), not raw.
// The plane count, the score before (2026-12-02), is dominated by the ground and the walls along
// the road, which any forward motion leaves planar: at 10 +- 4 m/s it chose 0.06 m of 1.03 m.
// Measured (docs/results/lidar.md, generic started at speed, 40 frames, RPE median): 10 +- 2
// m/s 3.6 mm (before 3.8), +- 4 m/s 4.8 mm (before 1.53 m), +- 6 m/s 4.9 mm (before 1.05 m).
#pragma once

#include <string>
#include <vector>

#include "plucker/geometry/se3.h"
#include "plucker/lidar/geometric_features.h"

namespace plucker {
namespace lidar {

struct SweepMotionSearch {
  double max_forward = 3.0;   // m per sweep (30 m/s at 10 Hz): grid of 13 values from 0
  double coarse_step = 0.25;  // m; the fine grid: quarters of it, +-4 around the best
  double max_yaw_deg = 12.0;  // per sweep: grid of 17 values over +-max_yaw
  double yaw_step_deg = 1.5;  // the fine grid: quarters of it, +-4 around the best
};

class SweepFeatureExtractor {
 public:
  // Features of `scan` (with a time channel) extracted after deskewing with T_start_end, moved
  // back to their measured positions. False with *error as GeometricFeatureExtractor.
  bool Extract(const LidarScan& scan, const SE3d& T_start_end, const FeatureOptions& ring_options,
               const GeometricFeatureOptions& options, ScanFeatures* features, std::string* error,
               Matrix6d* plane_information = nullptr);
  // The forward motion and yaw per sweep (SweepMotionSearch) whose deskewed cloud has the most
  // plane information about z (yaw) and along x (forward motion); see above.
  SE3d SearchForwardMotion(const LidarScan& scan, const FeatureOptions& ring_options,
                           const GeometricFeatureOptions& options,
                           const SweepMotionSearch& search = SweepMotionSearch());

 private:
  GeometricFeatureExtractor extractor_;
  LidarScan deskewed_;
};

}  // namespace lidar
}  // namespace plucker
