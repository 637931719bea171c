// What a camera front end (or the simulator) delivers per frame: image points and line segments,
// each with the id of the track (landmark) it belongs to. Pixel coordinates as in camera_rig.h.
#pragma once

#include <Eigen/Core>
#include <optional>

namespace plucker {
namespace sensor {

struct PointObservation {
  int frame = 0;
  int point_id = -1;  // track id (the simulator: index into its scene's points); -1 = outlier
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  // Image velocity of the track at this frame (px/s), for the camera-IMU time offset
  // (window::InertialOptions::estimate_time_offset). None: the window computes it from the
  // track's two previous observations. A given velocity should not be computed with this
  // observation (its noise would bias the offset), e.g. the flow between the two frames before.
  std::optional<Eigen::Vector2d> uv_velocity = std::nullopt;
  // The noise of uv when it is not the sequence's uniform pixel noise: the square-root
  // information relative to it (W with W^T W = Sigma^-1 sigma^2, Sigma the covariance of uv).
  // A fisheye's raw point mapped into its pinhole view (fisheye_rig.h) carries the inverse of
  // the mapping's Jacobian: its raw-pixel noise, stretched towards the view's edges. None: uniform.
  std::optional<Eigen::Matrix2d> sqrt_info_scale = std::nullopt;
};

struct SegmentObservation {
  int frame = 0;
  int line_id = -1;  // track id (the simulator: index into its scene's segments); -1 = outlier
  Eigen::Vector2d s_px = Eigen::Vector2d::Zero();  // start point
  Eigen::Vector2d e_px = Eigen::Vector2d::Zero();  // end point
  // Image velocities of the endpoints (px/s), as PointObservation::uv_velocity (both or none;
  // only their components normal to the segment matter).
  std::optional<Eigen::Vector2d> s_velocity = std::nullopt, e_velocity = std::nullopt;
};

// How the observations of a sequence were made: their pixel noise, the share of outliers, and
// what was observed (the simulator draws them so; a front end states its own).
struct ObservationModel {
  double pixel_sigma = 1.0;      // px, noise on every point / endpoint coordinate
  double outlier_ratio = 0.0;    // in [0, 0.9]: outliers / (inliers + outliers)
  double min_segment_px = 20.0;  // minimum (noise-free) segment length
  double min_depth = 0.1;        // m, features nearer than this are not observed
  double max_depth = 40.0;       // m, nor those farther than this
  bool observe_points = true;
  bool observe_segments = true;
};

}  // namespace sensor
}  // namespace plucker
