#include "plucker/geometry/so3.h"

namespace plucker {

namespace {
// Coefficients a = (1 - cos t)/t^2 and b = (t - sin t)/t^3 with series below 1e-4 rad.
void SO3JacobianCoefficients(double theta, double* a, double* b) {
  const double t2 = theta * theta;
  if (theta < 1e-4) {
    *a = 0.5 - t2 / 24.0;
    *b = 1.0 / 6.0 - t2 / 120.0;
  } else {
    *a = (1.0 - std::cos(theta)) / t2;
    *b = (theta - std::sin(theta)) / (t2 * theta);
  }
}

// c = 1/t^2 - (1 + cos t)/(2 t sin t); series 1/12 + t^2/720 near 0.
double SO3InverseCoefficient(double theta) {
  if (theta < 1e-4) return 1.0 / 12.0 + theta * theta / 720.0;
  return 1.0 / (theta * theta) - (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta));
}
}  // namespace

Eigen::Matrix3d LeftJacobianSO3(const Eigen::Vector3d& w) {
  double a, b;
  SO3JacobianCoefficients(w.norm(), &a, &b);
  const Eigen::Matrix3d W = Hat(w);
  return Eigen::Matrix3d::Identity() + a * W + b * W * W;
}

Eigen::Matrix3d RightJacobianSO3(const Eigen::Vector3d& w) { return LeftJacobianSO3(-w); }

Eigen::Matrix3d LeftJacobianInverseSO3(const Eigen::Vector3d& w) {
  const Eigen::Matrix3d W = Hat(w);
  return Eigen::Matrix3d::Identity() - 0.5 * W + SO3InverseCoefficient(w.norm()) * W * W;
}

Eigen::Matrix3d RightJacobianInverseSO3(const Eigen::Vector3d& w) {
  return LeftJacobianInverseSO3(-w);
}

Eigen::Matrix<double, 4, 3> QuaternionRightPlusJacobian(const Eigen::Quaterniond& q) {
  // q * (0.5 dtheta, 1): the quaternion product written as a 4x3 matrix in (x, y, z, w) order.
  const double x = q.x(), y = q.y(), z = q.z(), w = q.w();
  Eigen::Matrix<double, 4, 3> j;
  j << w, -z, y,  //
      z, w, -x,   //
      -y, x, w,   //
      -x, -y, -z;
  return 0.5 * j;
}

Eigen::Matrix<double, 3, 4> QuaternionRightMinusJacobian(const Eigen::Quaterniond& q0) {
  // Log(q0^-1 q) ~ 2 vec(q0^-1 q) near q0; for unit q0 this is 4 * PlusJacobian^T.
  return 4.0 * QuaternionRightPlusJacobian(q0).transpose();
}

}  // namespace plucker
