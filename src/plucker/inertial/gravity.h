// Gravity-aligned orientations (docs/math/vi-initialisation.md, "Tilt from the up vector").
//
// An accelerometer at rest measures the specific force f_b = R_w_b^T (0, 0, |g|) + b_a: the up
// direction of the world seen in the body frame. It fixes roll and pitch of R_w_b; the yaw about
// gravity is not observable and is set to zero here.
#pragma once

#include <Eigen/Core>

namespace plucker {
namespace inertial {

// The rotation R_w_b with R_w_b^T e_z = up_b / |up_b| and zero yaw in the ZYX (yaw, pitch, roll)
// decomposition R_w_b = Rz(0) Ry(pitch) Rx(roll), with
//   pitch = atan2(-u_x, sqrt(u_y^2 + u_z^2)),  roll = atan2(u_y, u_z).
// Defined for every non-zero up_b (roll is 0 when the body x axis is vertical). Throws
// std::invalid_argument for a zero or non-finite vector.
Eigen::Matrix3d GravityAlignedRotation(const Eigen::Vector3d& up_b);

// Angle between two non-zero vectors in radians, stable for small angles (atan2 of |a x b| and
// a . b).
double AngleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

// An orthonormal basis (3x2) of the plane orthogonal to the unit vector n.
Eigen::Matrix<double, 3, 2> TangentBasis(const Eigen::Vector3d& n);

}  // namespace inertial
}  // namespace plucker
