// The one way the analytic factors read a 7-value pose block and turn tangent Jacobians into
// ambient ones (lidar_factors.cc, point_reprojection_factor.cc, line_reprojection_factor.cc).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace plucker {
namespace pose_block {

// The block's unit quaternion, rotation matrix (if R is given) and translation. False for
// non-finite values or a quaternion whose squared norm is zero or overflows (the factors then
// return false from Evaluate).
inline bool Read(const double* x, Eigen::Quaterniond* q, Eigen::Matrix3d* R, Eigen::Vector3d* t) {
  for (int i = 0; i < 7; ++i)
    if (!std::isfinite(x[i])) return false;
  *q = Eigen::Quaterniond(x[3], x[0], x[1], x[2]);
  const double n2 = q->squaredNorm();
  if (!(n2 > 0.0) || !std::isfinite(n2)) return false;
  q->coeffs() /= std::sqrt(n2);
  if (R) *R = q->toRotationMatrix();
  *t = Eigen::Vector3d(x[4], x[5], x[6]);
  return true;
}

// Writes d r/d x (kRows x 7, row-major, as Ceres expects) from the tangent blocks d r/d dtheta
// (J_rot) and d r/d dt (J_t) at the unit quaternion q: J_ambient = [J_rot, J_t] *
// PoseManifold::MinusJacobian(x) (test PoseBlock.WriteAmbientIsTangentTimesMinusJacobian). The
// rotation block of MinusJacobian is 4 G(q)^T = 2 M(q)^T with G = QuaternionRightPlusJacobian(q)
// (geometry/so3.cc), expanded here by hand to avoid the 3x4 temporary.
template <int kRows, typename DerivedRot, typename DerivedT>
inline void WriteAmbient(const Eigen::MatrixBase<DerivedRot>& J_rot,
                         const Eigen::MatrixBase<DerivedT>& J_t, const Eigen::Quaterniond& q,
                         double* jacobian) {
  const double x2 = 2.0 * q.x(), y2 = 2.0 * q.y(), z2 = 2.0 * q.z(), w2 = 2.0 * q.w();
  for (int r = 0; r < kRows; ++r) {
    const double j0 = J_rot(r, 0), j1 = J_rot(r, 1), j2 = J_rot(r, 2);
    double* row = jacobian + 7 * r;
    row[0] = w2 * j0 - z2 * j1 + y2 * j2;
    row[1] = z2 * j0 + w2 * j1 - x2 * j2;
    row[2] = -y2 * j0 + x2 * j1 + w2 * j2;
    row[3] = -x2 * j0 - y2 * j1 - z2 * j2;
    row[4] = J_t(r, 0);
    row[5] = J_t(r, 1);
    row[6] = J_t(r, 2);
  }
}

}  // namespace pose_block
}  // namespace plucker
