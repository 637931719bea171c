// Rigid transforms T_a_b = (R_a_b, t_a_b): p_a = R_a_b p_b + t_a_b.
//
// Storage of a pose parameter block (7 doubles): [qx, qy, qz, qw, tx, ty, tz], i.e. Eigen's
// quaternion coefficients followed by the translation (the layout of Sophus::SE3d::data()).
//
// Tangent convention used by every Jacobian of this file and by the pose manifold
// (factors/pose_manifold.h): delta = (dtheta, dt), rotation first, with
//   R <- R Exp(dtheta)     (right perturbation of the rotation)
//   t <- t + dt            (translation added in the target frame a)
// This is the SO(3) x R(3) retraction; docs/conventions.md explains the choice.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "plucker/geometry/so3.h"

namespace plucker {

template <typename T>
class SE3 {
 public:
  using Quaternion = Eigen::Quaternion<T>;
  using Vector = Vector3<T>;

  SE3() : q_(Quaternion::Identity()), t_(Vector::Zero()) {}
  SE3(const Quaternion& q, const Vector& t) : q_(q.normalized()), t_(t) {}
  SE3(const Matrix3<T>& R, const Vector& t) : q_(Quaternion(R).normalized()), t_(t) {}

  // From a 7-value parameter block [qx, qy, qz, qw, tx, ty, tz] (not required to be normalized).
  static SE3 FromParameters(const T* p) {
    return SE3(Quaternion(p[3], p[0], p[1], p[2]), Vector(p[4], p[5], p[6]));
  }
  void ToParameters(T* p) const {
    p[0] = q_.x();
    p[1] = q_.y();
    p[2] = q_.z();
    p[3] = q_.w();
    p[4] = t_.x();
    p[5] = t_.y();
    p[6] = t_.z();
  }
  static SE3 FromMatrix(const Eigen::Matrix<T, 4, 4>& m) {
    return SE3(Matrix3<T>(m.template topLeftCorner<3, 3>()),
               Vector(m.template topRightCorner<3, 1>()));
  }
  // Exp of the (dtheta, dt) tangent from the identity: (Exp(dtheta), dt).
  static SE3 Retract(const Eigen::Matrix<T, 6, 1>& delta) {
    return SE3(ExpSO3<T>(delta.template head<3>()), delta.template tail<3>());
  }

  const Quaternion& rotation() const { return q_; }
  const Vector& translation() const { return t_; }
  Matrix3<T> RotationMatrix() const { return q_.toRotationMatrix(); }
  Eigen::Matrix<T, 4, 4> Matrix() const {
    Eigen::Matrix<T, 4, 4> m = Eigen::Matrix<T, 4, 4>::Identity();
    m.template topLeftCorner<3, 3>() = RotationMatrix();
    m.template topRightCorner<3, 1>() = t_;
    return m;
  }

  SE3 Inverse() const {
    const Quaternion q_inv = q_.conjugate();
    return SE3(q_inv, -(q_inv * t_));
  }
  SE3 operator*(const SE3& other) const { return SE3(q_ * other.q_, q_ * other.t_ + t_); }
  Vector operator*(const Vector& p) const { return q_ * p + t_; }

  // The manifold update: (R Exp(dtheta), t + dt).
  SE3 Plus(const Eigen::Matrix<T, 6, 1>& delta) const {
    return SE3(q_ * ExpSO3<T>(delta.template head<3>()), t_ + delta.template tail<3>());
  }
  // Inverse of Plus: (Log(q_base^-1 q_this), t_this - t_base), the quaternion log taken on S^3
  // so that base.Plus(this->Minus(base)) reproduces this quaternion's coefficients exactly.
  Eigen::Matrix<T, 6, 1> Minus(const SE3& base) const {
    Eigen::Matrix<T, 6, 1> d;
    d.template head<3>() = LogUnitQuaternion<T>(base.q_.conjugate() * q_);
    d.template tail<3>() = t_ - base.t_;
    return d;
  }

  template <typename U>
  SE3<U> cast() const {
    return SE3<U>(q_.template cast<U>(), t_.template cast<U>());
  }

 private:
  Quaternion q_;
  Vector t_;
};

using SE3d = SE3<double>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

// T_a_c = T_a_b * T_b_c with Jacobians (6x6, tangent (dtheta, dt) on each side).
SE3d Compose(const SE3d& T_a_b, const SE3d& T_b_c, Matrix6d* d_ac_d_ab = nullptr,
             Matrix6d* d_ac_d_bc = nullptr);
// T_b_a = T_a_b^-1 with its Jacobian.
SE3d Inverse(const SE3d& T_a_b, Matrix6d* d_ba_d_ab = nullptr);
// p_a = T_a_b * p_b with Jacobians w.r.t. the pose (3x6) and the point (3x3).
Eigen::Vector3d TransformPoint(const SE3d& T_a_b, const Eigen::Vector3d& p_b,
                               Eigen::Matrix<double, 3, 6>* d_pa_d_pose = nullptr,
                               Eigen::Matrix3d* d_pa_d_pb = nullptr);

}  // namespace plucker
