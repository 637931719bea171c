// SO(3): hat/vee, exponential and logarithm (stable near 0 and near pi), left/right Jacobians.
//
// Conventions (docs/conventions.md): rotation vectors are axis * angle; quaternions are Eigen
// quaternions (storage order x, y, z, w); a rotation R_a_b maps frame-b coordinates into frame a.
// The value functions are templates so that they run with ceres::Jet in the autodiff twins; the
// analytic Jacobians are double-only.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace plucker {

template <typename T>
using Vector3 = Eigen::Matrix<T, 3, 1>;
template <typename T>
using Matrix3 = Eigen::Matrix<T, 3, 3>;

// [v]x: the skew-symmetric matrix with [v]x w = v x w.
template <typename T>
Matrix3<T> Hat(const Vector3<T>& v) {
  Matrix3<T> m;
  m << T(0), -v(2), v(1), v(2), T(0), -v(0), -v(1), v(0), T(0);
  return m;
}

template <typename T>
Vector3<T> Vee(const Matrix3<T>& m) {
  return Vector3<T>(m(2, 1), m(0, 2), m(1, 0));
}

// Exp: rotation vector -> unit quaternion. Taylor expansion below 1e-8 rad^2 keeps it exact to
// machine precision and differentiable (with Jets) at zero.
template <typename T>
Eigen::Quaternion<T> ExpSO3(const Vector3<T>& w) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const T theta_sq = w.squaredNorm();
  T real, imag_factor;
  if (theta_sq < T(1e-8)) {
    real = T(1) - theta_sq / T(8);
    imag_factor = T(0.5) - theta_sq / T(48);
  } else {
    const T theta = sqrt(theta_sq);
    const T half = theta / T(2);
    real = cos(half);
    imag_factor = sin(half) / theta;
  }
  return Eigen::Quaternion<T>(real, imag_factor * w(0), imag_factor * w(1), imag_factor * w(2));
}

// Logarithm on the unit-quaternion sphere S^3 (no sign flip): the rotation vector w, |w| in
// [0, 2 pi), with ExpSO3(w) == q exactly (not -q). This is what a quaternion manifold's Minus needs
// so that Plus(x, Minus(y, x)) == y holds for the stored coefficients. Undefined only at q = -1.
template <typename T>
Vector3<T> LogUnitQuaternion(const Eigen::Quaternion<T>& q) {
  using std::atan2;
  using std::sqrt;
  const T sin_half_sq = q.vec().squaredNorm();
  T factor;
  if (sin_half_sq < T(1e-16) && q.w() > T(0)) {
    // theta/sin(theta/2) ~ 2/w (1 - sin_half^2 / (3 w^2)).
    const T w = q.w();
    factor = T(2) / w - T(2) / T(3) * sin_half_sq / (w * w * w);
  } else {
    const T sin_half = sqrt(sin_half_sq);
    factor = T(2) * atan2(sin_half, q.w()) / sin_half;
  }
  return factor * q.vec();
}

// Log on SO(3): unit quaternion -> rotation vector with angle in [0, pi] (q and -q give the same
// result). atan2 keeps it stable near pi (w -> 0) as well as near the identity.
template <typename T>
Vector3<T> LogSO3(const Eigen::Quaternion<T>& q_in) {
  Eigen::Quaternion<T> q = q_in;
  if (q.w() < T(0)) q.coeffs() = -q.coeffs();
  return LogUnitQuaternion(q);
}

template <typename T>
Matrix3<T> ExpSO3Matrix(const Vector3<T>& w) {
  return ExpSO3(w).toRotationMatrix();
}

// Right Jacobian Jr(w): Exp(w + dw) ~ Exp(w) Exp(Jr(w) dw).
Eigen::Matrix3d RightJacobianSO3(const Eigen::Vector3d& w);
// Inverse of the right Jacobian: Log(Exp(w) Exp(dw)) ~ w + Jr^-1(w) dw.
Eigen::Matrix3d RightJacobianInverseSO3(const Eigen::Vector3d& w);
// Left Jacobian Jl(w) = Jr(-w): Exp(w + dw) ~ Exp(Jl(w) dw) Exp(w).
Eigen::Matrix3d LeftJacobianSO3(const Eigen::Vector3d& w);
Eigen::Matrix3d LeftJacobianInverseSO3(const Eigen::Vector3d& w);

// d(q_plus)/d(dtheta) at dtheta = 0 for q_plus = q * Exp(dtheta), as a 4x3 block in Eigen
// coefficient order (x, y, z, w). Used by the manifolds' PlusJacobian.
Eigen::Matrix<double, 4, 3> QuaternionRightPlusJacobian(const Eigen::Quaterniond& q);
// d Log(q0^-1 * q)/d q at q = q0 (3x4, coefficients x, y, z, w): the MinusJacobian counterpart.
Eigen::Matrix<double, 3, 4> QuaternionRightMinusJacobian(const Eigen::Quaterniond& q0);

}  // namespace plucker
