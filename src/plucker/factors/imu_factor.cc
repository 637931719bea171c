#include "plucker/factors/imu_factor.h"

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Cholesky>
#include <stdexcept>

#include "plucker/factors/pose_block.h"

namespace plucker {

namespace {

using Matrix9x3 = Eigen::Matrix<double, 9, 3>;

bool Finite(const double* x, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(x[i])) return false;
  return true;
}

// S with S^T S = Sigma^-1: for Sigma = L L^T, S = L^-1.
Matrix15d SqrtInformation(const ImuPreintegration& p) {
  const Matrix15d& covariance = p.JointCovariance();
  const Eigen::LLT<Matrix15d> llt(covariance);
  if (llt.info() != Eigen::Success) {
    throw std::invalid_argument("ImuFactor: preintegration covariance is not positive definite");
  }
  const Matrix15d S = llt.matrixL().solve(Matrix15d::Identity());
  if (!S.allFinite()) throw std::invalid_argument("ImuFactor: non-finite information");
  return S;
}

template <typename Derived>
void WriteBlock(const Eigen::MatrixBase<Derived>& J, double* jacobian) {
  Eigen::Map<Eigen::Matrix<double, 15, Derived::ColsAtCompileTime, Eigen::RowMajor>> out(jacobian);
  out = J;
}

}  // namespace

ImuMeasurement MakeImuMeasurement(const ImuPreintegration& p, const Eigen::Vector3d& gravity_w) {
  if (p.NumSamples() == 0) throw std::invalid_argument("ImuFactor: preintegration has no samples");
  if (!gravity_w.allFinite()) throw std::invalid_argument("ImuFactor: non-finite gravity");
  ImuMeasurement m;
  m.dt = p.Dt();
  m.delta_R = p.DeltaR();
  m.delta_v = p.DeltaV();
  m.delta_p = p.DeltaP();
  m.d_R_d_bg = p.d_R_d_bg();
  m.d_v_d_bg = p.d_v_d_bg();
  m.d_v_d_ba = p.d_v_d_ba();
  m.d_p_d_bg = p.d_p_d_bg();
  m.d_p_d_ba = p.d_p_d_ba();
  m.bias_lin = p.BiasLinearisation();
  m.gravity_w = gravity_w;
  m.sqrt_information = SqrtInformation(p);
  return m;
}

ceres::CostFunction* ImuFactor::Create(const ImuPreintegration& preintegration,
                                       const Eigen::Vector3d& gravity_w) {
  return new ImuFactor(MakeImuMeasurement(preintegration, gravity_w));
}

ceres::CostFunction* ImuFactor::CreateAutoDiff(const ImuPreintegration& preintegration,
                                               const Eigen::Vector3d& gravity_w) {
  return new ceres::AutoDiffCostFunction<ImuResidual, 15, 7, 3, 6, 7, 3, 6>(
      new ImuResidual{MakeImuMeasurement(preintegration, gravity_w)});
}

bool ImuFactor::Evaluate(double const* const* parameters, double* residuals,
                         double** jacobians) const {
  Eigen::Quaterniond q_i, q_j;
  Eigen::Matrix3d R_i, R_j;
  Eigen::Vector3d p_i, p_j;
  if (!pose_block::Read(parameters[0], &q_i, &R_i, &p_i) ||
      !pose_block::Read(parameters[3], &q_j, &R_j, &p_j) || !Finite(parameters[1], 3) ||
      !Finite(parameters[2], 6) || !Finite(parameters[4], 3) || !Finite(parameters[5], 6)) {
    return false;
  }
  const Eigen::Matrix<double, 15, 1> r =
      ImuResidualT<double>(m_, SE3d(q_i, p_i), parameters[1], parameters[2], SE3d(q_j, p_j),
                           parameters[4], parameters[5]);
  Eigen::Map<Eigen::Matrix<double, 15, 1>> weighted(residuals);
  weighted = m_.sqrt_information.lazyProduct(r);
  if (!jacobians) return true;

  const Eigen::Map<const Eigen::Vector3d> v_i(parameters[1]), v_j(parameters[4]);
  const Eigen::Map<const Eigen::Vector3d> bg_i(parameters[2]);
  const double dt = m_.dt;
  const Eigen::Matrix3d R_i_T = R_i.transpose();
  const Eigen::Vector3d r_R = r.head<3>();
  const Eigen::Matrix3d Jr_inv = RightJacobianInverseSO3(r_R);
  const Eigen::Vector3d phi = m_.d_R_d_bg * (bg_i - m_.bias_lin.gyro);
  const Eigen::Matrix3d M_T = ExpSO3Matrix<double>(r_R).transpose();  // (R_c^T R_i^T R_j)^T
  const Eigen::Vector3d u = v_j - v_i - m_.gravity_w * dt;
  const Eigen::Vector3d s = p_j - p_i - v_i * dt - 0.5 * m_.gravity_w * dt * dt;
  // Every block's unweighted Jacobian is [J9; J_bias] with J9 on the rows [r_R, r_v, r_p] and
  // J_bias = 0, -I or +I on the bias rows: whiten the two parts apart (S is 15x15, lower
  // triangular; lazyProduct keeps these small fixed-size products out of Eigen's GEMM path).
  const auto S9 = m_.sqrt_information.leftCols<9>();
  const auto S_bias = m_.sqrt_information.rightCols<6>();

  if (jacobians[0]) {  // T_w_b_i: rotation and translation tangents
    Matrix9x3 J_rot, J_t = Matrix9x3::Zero();
    J_rot << -Jr_inv * R_j.transpose() * R_i, Hat<double>(R_i_T * u), Hat<double>(R_i_T * s);
    J_t.bottomRows<3>() = -R_i_T;
    pose_block::WriteAmbient<15>(S9.lazyProduct(J_rot), S9.lazyProduct(J_t), q_i, jacobians[0]);
  }
  if (jacobians[1]) {  // v_i
    Matrix9x3 J;
    J << Eigen::Matrix3d::Zero(), -R_i_T, -R_i_T * dt;
    WriteBlock(S9.lazyProduct(J), jacobians[1]);
  }
  if (jacobians[2]) {  // bias_i = [b_g, b_a]
    Eigen::Matrix<double, 9, 6> J = Eigen::Matrix<double, 9, 6>::Zero();
    J.block<3, 3>(0, 0) = -Jr_inv * M_T * RightJacobianSO3(phi) * m_.d_R_d_bg;
    J.block<3, 3>(3, 0) = -m_.d_v_d_bg;
    J.block<3, 3>(3, 3) = -m_.d_v_d_ba;
    J.block<3, 3>(6, 0) = -m_.d_p_d_bg;
    J.block<3, 3>(6, 3) = -m_.d_p_d_ba;
    WriteBlock(S9.lazyProduct(J) - S_bias, jacobians[2]);
  }
  if (jacobians[3]) {  // T_w_b_j
    Matrix9x3 J_rot = Matrix9x3::Zero(), J_t = Matrix9x3::Zero();
    J_rot.topRows<3>() = Jr_inv;
    J_t.bottomRows<3>() = R_i_T;
    pose_block::WriteAmbient<15>(S9.lazyProduct(J_rot), S9.lazyProduct(J_t), q_j, jacobians[3]);
  }
  if (jacobians[4]) {  // v_j
    Matrix9x3 J = Matrix9x3::Zero();
    J.middleRows<3>(3) = R_i_T;
    WriteBlock(S9.lazyProduct(J), jacobians[4]);
  }
  if (jacobians[5]) WriteBlock(S_bias, jacobians[5]);  // bias_j
  return true;
}

}  // namespace plucker
