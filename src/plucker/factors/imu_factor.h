// The IMU preintegration factor between keyframes i and j (docs/math/imu-preintegration.md).
//
// Parameter blocks: T_w_b_i (pose block, 7), v_w_i (3), bias_i = [b_g, b_a] (6),
//                   T_w_b_j (7), v_w_j (3), bias_j (6).
// Residual (15) = S [r_R, r_v, r_p, r_bg, r_ba] with S the square-root information of the
// preintegration's joint covariance (ImuPreintegration::JointCovariance) and, for
// d_g = b_g_i - b_g_lin, d_a = b_a_i - b_a_lin (first-order bias correction):
//   r_R  = Log((DR Exp(dR_dbg d_g))^T R_i^T R_j)
//   r_v  = R_i^T (v_j - v_i - g Dt) - (Dv + dv_dbg d_g + dv_dba d_a)
//   r_p  = R_i^T (p_j - p_i - v_i Dt - 1/2 g Dt^2) - (Dp + dp_dbg d_g + dp_dba d_a)
//   r_bg = b_g_j - b_g_i,   r_ba = b_a_j - b_a_i
// Jacobians: tangent blocks by hand (docs/math), then pose_block::WriteAmbient for the poses, as
// every factor here. Immutable: the factor copies the preintegrated values it needs.
//
// Errors: Create/CreateAutoDiff throw std::invalid_argument for a preintegration without samples,
// a non-finite gravity, or a covariance that is not positive definite. Evaluate returns false for
// non-finite parameters or a zero quaternion.
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "plucker/factors/imu_preintegration.h"
#include "plucker/geometry/se3.h"

namespace plucker {

// The values the factor keeps from a preintegration.
struct ImuMeasurement {
  double dt = 0.0;
  Eigen::Matrix3d delta_R;
  Eigen::Vector3d delta_v, delta_p;
  Eigen::Matrix3d d_R_d_bg, d_v_d_bg, d_v_d_ba, d_p_d_bg, d_p_d_ba;
  sensor::ImuBias bias_lin;
  Eigen::Vector3d gravity_w;
  Matrix15d sqrt_information;
};

// Throws std::invalid_argument as documented above.
ImuMeasurement MakeImuMeasurement(const ImuPreintegration& preintegration,
                                  const Eigen::Vector3d& gravity_w);

// The 15 unweighted residuals as a template (the autodiff twin and the analytic value share it).
template <typename T>
Eigen::Matrix<T, 15, 1> ImuResidualT(const ImuMeasurement& m, const SE3<T>& T_w_b_i, const T* v_i,
                                     const T* bias_i, const SE3<T>& T_w_b_j, const T* v_j,
                                     const T* bias_j) {
  using V3 = Eigen::Matrix<T, 3, 1>;
  const V3 vi(v_i[0], v_i[1], v_i[2]), vj(v_j[0], v_j[1], v_j[2]);
  const V3 bg_i(bias_i[0], bias_i[1], bias_i[2]), ba_i(bias_i[3], bias_i[4], bias_i[5]);
  const V3 bg_j(bias_j[0], bias_j[1], bias_j[2]), ba_j(bias_j[3], bias_j[4], bias_j[5]);
  const V3 d_g = bg_i - m.bias_lin.gyro.cast<T>(), d_a = ba_i - m.bias_lin.accel.cast<T>();
  const V3 g = m.gravity_w.cast<T>();
  const T dt(m.dt);
  const Eigen::Quaternion<T> q_corr =
      Eigen::Quaternion<T>(m.delta_R.cast<T>()) * ExpSO3<T>(V3(m.d_R_d_bg.cast<T>() * d_g));
  const Eigen::Quaternion<T> q_i = T_w_b_i.rotation(), q_j = T_w_b_j.rotation();
  const Matrix3<T> R_i_T = q_i.toRotationMatrix().transpose();
  Eigen::Matrix<T, 15, 1> r;
  r.template segment<3>(0) = LogSO3<T>(q_corr.conjugate() * q_i.conjugate() * q_j);
  r.template segment<3>(3) =
      R_i_T * (vj - vi - g * dt) -
      (m.delta_v.cast<T>() + m.d_v_d_bg.cast<T>() * d_g + m.d_v_d_ba.cast<T>() * d_a);
  r.template segment<3>(6) =
      R_i_T * (T_w_b_j.translation() - T_w_b_i.translation() - vi * dt - T(0.5) * g * dt * dt) -
      (m.delta_p.cast<T>() + m.d_p_d_bg.cast<T>() * d_g + m.d_p_d_ba.cast<T>() * d_a);
  r.template segment<3>(9) = bg_j - bg_i;
  r.template segment<3>(12) = ba_j - ba_i;
  return r;
}

// Autodiff twin.
struct ImuResidual {
  ImuMeasurement m;
  template <typename T>
  bool operator()(const T* pose_i, const T* v_i, const T* bias_i, const T* pose_j, const T* v_j,
                  const T* bias_j, T* residual) const {
    Eigen::Map<Eigen::Matrix<T, 15, 1>> r(residual);
    r = m.sqrt_information.cast<T>() * ImuResidualT<T>(m, SE3<T>::FromParameters(pose_i), v_i,
                                                       bias_i, SE3<T>::FromParameters(pose_j), v_j,
                                                       bias_j);
    return true;
  }
};

class ImuFactor final : public ceres::SizedCostFunction<15, 7, 3, 6, 7, 3, 6> {
 public:
  static ceres::CostFunction* Create(const ImuPreintegration& preintegration,
                                     const Eigen::Vector3d& gravity_w);
  static ceres::CostFunction* CreateAutoDiff(const ImuPreintegration& preintegration,
                                             const Eigen::Vector3d& gravity_w);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  explicit ImuFactor(const ImuMeasurement& m) : m_(m) {}
  const ImuMeasurement m_;
};

}  // namespace plucker
