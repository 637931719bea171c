#include "plucker/geometry/se3.h"

namespace plucker {

SE3d Compose(const SE3d& T_a_b, const SE3d& T_b_c, Matrix6d* d_ac_d_ab, Matrix6d* d_ac_d_bc) {
  const Eigen::Matrix3d R_a_b = T_a_b.RotationMatrix();
  const Eigen::Matrix3d R_b_c = T_b_c.RotationMatrix();
  if (d_ac_d_ab) {
    // R_a_b Exp(dth) R_b_c = R_a_c Exp(R_b_c^T dth); t = R_a_b Exp(dth) t_b_c + t_a_b + dt.
    d_ac_d_ab->setZero();
    d_ac_d_ab->block<3, 3>(0, 0) = R_b_c.transpose();
    d_ac_d_ab->block<3, 3>(3, 0) = -R_a_b * Hat<double>(T_b_c.translation());
    d_ac_d_ab->block<3, 3>(3, 3).setIdentity();
  }
  if (d_ac_d_bc) {
    d_ac_d_bc->setZero();
    d_ac_d_bc->block<3, 3>(0, 0).setIdentity();
    d_ac_d_bc->block<3, 3>(3, 3) = R_a_b;
  }
  return T_a_b * T_b_c;
}

SE3d Inverse(const SE3d& T_a_b, Matrix6d* d_ba_d_ab) {
  const SE3d T_b_a = T_a_b.Inverse();
  if (d_ba_d_ab) {
    // (R Exp(dth))^T = R^T Exp(-R dth); t_b_a(dth) = -Exp(-dth) R^T t ~ t_b_a + [t_b_a]x dth.
    const Eigen::Matrix3d R = T_a_b.RotationMatrix();
    d_ba_d_ab->setZero();
    d_ba_d_ab->block<3, 3>(0, 0) = -R;
    d_ba_d_ab->block<3, 3>(3, 0) = Hat<double>(T_b_a.translation());
    d_ba_d_ab->block<3, 3>(3, 3) = -R.transpose();
  }
  return T_b_a;
}

Eigen::Vector3d TransformPoint(const SE3d& T_a_b, const Eigen::Vector3d& p_b,
                               Eigen::Matrix<double, 3, 6>* d_pa_d_pose,
                               Eigen::Matrix3d* d_pa_d_pb) {
  const Eigen::Matrix3d R = T_a_b.RotationMatrix();
  if (d_pa_d_pose) {
    d_pa_d_pose->block<3, 3>(0, 0) = -R * Hat<double>(p_b);
    d_pa_d_pose->block<3, 3>(0, 3).setIdentity();
  }
  if (d_pa_d_pb) *d_pa_d_pb = R;
  return R * p_b + T_a_b.translation();
}

}  // namespace plucker
