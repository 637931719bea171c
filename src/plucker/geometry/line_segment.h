// A 3D line segment by its two endpoints, in the frame its suffix names (here the world w):
// scene structure for simulation and ground truth.
#pragma once

#include <Eigen/Core>

namespace plucker {

struct LineSegment3 {
  Eigen::Vector3d a_w = Eigen::Vector3d::Zero();  // endpoints, a_w != b_w
  Eigen::Vector3d b_w = Eigen::Vector3d::UnitX();
};

}  // namespace plucker
