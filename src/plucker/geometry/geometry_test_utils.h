// Helpers shared by the geometry tests (not installed).
#pragma once

#include <Eigen/Geometry>
#include <cmath>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/se3.h"

namespace plucker {
namespace testing_utils {

// Intrinsics with distinct fx, fy so that axis mix-ups show.
inline PinholeIntrinsics TestK() { return {500, 480, 320, 240}; }

// Camera pose T_w_c at centre c looking at target (z axis towards it), rolled about the viewing
// axis.
inline SE3d LookAt(const Eigen::Vector3d& c, const Eigen::Vector3d& target, double roll = 0.0) {
  const Eigen::Vector3d z = (target - c).normalized();
  const Eigen::Vector3d a =
      std::abs(z.y()) < 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d x = a.cross(z).normalized();
  Eigen::Matrix3d R;
  R << x, z.cross(x), z;
  return SE3d(Eigen::Matrix3d(R * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ())), c);
}

}  // namespace testing_utils
}  // namespace plucker
