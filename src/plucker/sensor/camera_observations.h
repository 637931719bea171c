// What a camera front end (or the simulator) delivers per frame: image points and line segments,
// each with the id of the track (landmark) it belongs to. Pixel coordinates as in camera_rig.h.
#pragma once

#include <Eigen/Core>

namespace plucker {
namespace sensor {

struct PointObservation {
  int frame = 0;
  int point_id = -1;  // track id (the simulator: index into its scene's points); -1 = outlier
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
};

struct SegmentObservation {
  int frame = 0;
  int line_id = -1;  // track id (the simulator: index into its scene's segments); -1 = outlier
  Eigen::Vector2d s_px = Eigen::Vector2d::Zero();  // start point
  Eigen::Vector2d e_px = Eigen::Vector2d::Zero();  // end point
};

}  // namespace sensor
}  // namespace plucker
