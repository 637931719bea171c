#include "plucker/inertial/gravity.h"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

namespace plucker {
namespace inertial {

Eigen::Matrix3d GravityAlignedRotation(const Eigen::Vector3d& up_b) {
  const double norm = up_b.norm();
  if (!std::isfinite(norm) || norm <= 0.0) {
    throw std::invalid_argument("GravityAlignedRotation: the up vector must be finite, non-zero");
  }
  const Eigen::Vector3d u = up_b / norm;
  const double pitch = std::atan2(-u.x(), std::hypot(u.y(), u.z()));
  const double roll = std::atan2(u.y(), u.z());
  return (Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

double AngleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

Eigen::Matrix<double, 3, 2> TangentBasis(const Eigen::Vector3d& n) {
  // The axis least aligned with n gives a well-conditioned first tangent.
  Eigen::Vector3d other = Eigen::Vector3d::UnitX();
  if (std::abs(n.x()) > std::abs(n.y()) || std::abs(n.x()) > std::abs(n.z())) {
    other = std::abs(n.y()) < std::abs(n.z()) ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
  }
  Eigen::Matrix<double, 3, 2> B;
  B.col(0) = n.cross(other).normalized();
  B.col(1) = n.cross(B.col(0)).normalized();
  return B;
}

}  // namespace inertial
}  // namespace plucker
