#include "plucker/factors/pose_manifold.h"

#include <Eigen/Core>

#include "plucker/geometry/se3.h"

namespace plucker {

namespace {
bool AllFinite(const double* v, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}
}  // namespace

bool PoseManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  if (!AllFinite(x, 7) || !AllFinite(delta, 6)) return false;
  const SE3d pose = SE3d::FromParameters(x);
  pose.Plus(Eigen::Map<const Vector6d>(delta)).ToParameters(x_plus_delta);
  return true;
}

bool PoseManifold::PlusJacobian(const double* x, double* jacobian) const {
  if (!AllFinite(x, 7)) return false;
  Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  const Eigen::Quaterniond q(x[3], x[0], x[1], x[2]);
  J.block<4, 3>(0, 0) = QuaternionRightPlusJacobian(q.normalized());
  J.block<3, 3>(4, 3).setIdentity();
  return true;
}

bool PoseManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  if (!AllFinite(x, 7) || !AllFinite(y, 7)) return false;
  Eigen::Map<Vector6d> out(y_minus_x);
  out = SE3d::FromParameters(y).Minus(SE3d::FromParameters(x));
  return true;
}

bool PoseManifold::MinusJacobian(const double* x, double* jacobian) const {
  if (!AllFinite(x, 7)) return false;
  Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  const Eigen::Quaterniond q(x[3], x[0], x[1], x[2]);
  J.block<3, 4>(0, 0) = QuaternionRightMinusJacobian(q.normalized());
  J.block<3, 3>(3, 4).setIdentity();
  return true;
}

namespace {
// R^T [e_x, e_y]: world x, y rotations in the body tangent (orthonormal columns).
Eigen::Matrix<double, 3, 2> WorldRollPitchInBody(const double* x) {
  return SE3d::FromParameters(x).RotationMatrix().transpose().leftCols<2>();
}
}  // namespace

bool RollPitchPoseManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
  d.head<3>() = WorldRollPitchInBody(x) * Eigen::Map<const Eigen::Vector2d>(delta);
  return pose_.Plus(x, d.data(), x_plus_delta);
}

bool RollPitchPoseManifold::PlusJacobian(const double* x, double* jacobian) const {
  Eigen::Matrix<double, 7, 6, Eigen::RowMajor> J;
  if (!pose_.PlusJacobian(x, J.data())) return false;
  Eigen::Map<Eigen::Matrix<double, 7, 2, Eigen::RowMajor>> out(jacobian);
  out = J.leftCols<3>() * WorldRollPitchInBody(x);
  return true;
}

bool RollPitchPoseManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  Eigen::Matrix<double, 6, 1> d;
  if (!pose_.Minus(y, x, d.data())) return false;
  Eigen::Map<Eigen::Vector2d> out(y_minus_x);
  out = WorldRollPitchInBody(x).transpose() * d.head<3>();
  return true;
}

bool RollPitchPoseManifold::MinusJacobian(const double* x, double* jacobian) const {
  Eigen::Matrix<double, 6, 7, Eigen::RowMajor> J;
  if (!pose_.MinusJacobian(x, J.data())) return false;
  Eigen::Map<Eigen::Matrix<double, 2, 7, Eigen::RowMajor>> out(jacobian);
  out = WorldRollPitchInBody(x).transpose() * J.topRows<3>();
  return true;
}

}  // namespace plucker
