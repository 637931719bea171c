#include "plucker/factors/point_reprojection_factor.h"

#include <stdexcept>

#include "plucker/factors/pose_block.h"

namespace plucker {

namespace {

bool FinitePoint(const double* p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

// r = S (pi(p_c) - uv). With d_r_d_pc, also S d_uv/d_p_c, the link every block's Jacobian starts
// from. False when p_c is not in front of the camera.
bool WhitenedResidual(const PointObservation& obs, const Eigen::Vector3d& p_c, double* residuals,
                      Eigen::Matrix<double, 2, 3>* d_r_d_pc) {
  Eigen::Matrix<double, 2, 3> d_uv_d_pc;
  const std::optional<Eigen::Vector2d> uv =
      ProjectCameraPoint(obs.K, p_c, d_r_d_pc ? &d_uv_d_pc : nullptr, kPointMinDepth);
  if (!uv) return false;
  Eigen::Map<Eigen::Vector2d> r(residuals);
  r = obs.sqrt_information * (*uv - obs.uv);
  if (d_r_d_pc) *d_r_d_pc = obs.sqrt_information * d_uv_d_pc;
  return true;
}

}  // namespace

PointObservation MakePointObservation(const PinholeIntrinsics& K, const Eigen::Vector2d& uv,
                                      const Eigen::Matrix2d& sqrt_information) {
  if (!K.IsValid()) {
    throw std::invalid_argument(
        "PointReprojectionFactor: invalid intrinsics (need finite values and fx, fy > 0)");
  }
  if (!uv.allFinite()) throw std::invalid_argument("PointReprojectionFactor: non-finite pixel");
  if (!sqrt_information.allFinite()) {
    throw std::invalid_argument("PointReprojectionFactor: non-finite sqrt_information");
  }
  return {K, uv, sqrt_information};
}

// ---------------------------------------------------------------- PointReprojectionFactor

ceres::CostFunction* PointReprojectionFactor::Create(const PinholeIntrinsics& K,
                                                     const Eigen::Vector2d& uv,
                                                     const Eigen::Matrix2d& sqrt_information) {
  return new PointReprojectionFactor(MakePointObservation(K, uv, sqrt_information));
}

ceres::CostFunction* PointReprojectionFactor::CreateAutoDiff(
    const PinholeIntrinsics& K, const Eigen::Vector2d& uv,
    const Eigen::Matrix2d& sqrt_information) {
  return new ceres::AutoDiffCostFunction<PointReprojectionResidual, 2, 7, 3>(
      new PointReprojectionResidual{MakePointObservation(K, uv, sqrt_information)});
}

bool PointReprojectionFactor::Evaluate(double const* const* parameters, double* residuals,
                                       double** jacobians) const {
  Eigen::Quaterniond q;
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  if (!pose_block::Read(parameters[0], &q, &R, &t) || !FinitePoint(parameters[1])) return false;
  const Eigen::Map<const Eigen::Vector3d> p_w(parameters[1]);
  // p_c = R^T (p_w - t).
  const Eigen::Vector3d p_c = R.transpose() * (p_w - t);
  const bool need_j = jacobians && (jacobians[0] || jacobians[1]);
  // A = S d_uv/d_p_c;  d p_c/d p_w = R^T,  d p_c/d dtheta = [p_c]x,  d p_c/d dt = -R^T.
  Eigen::Matrix<double, 2, 3> A;
  if (!WhitenedResidual(obs_, p_c, residuals, need_j ? &A : nullptr)) return false;
  if (!need_j) return true;
  const Eigen::Matrix<double, 2, 3> d_r_d_pw = A * R.transpose();
  if (jacobians[0]) {
    pose_block::WriteAmbient<2>(A * Hat<double>(p_c), -d_r_d_pw, q, jacobians[0]);
  }
  if (jacobians[1]) {
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> J_pw(jacobians[1]);
    J_pw = d_r_d_pw;
  }
  return true;
}

// ---------------------------------------------------------------- PointReprojectionFactorVI

ceres::CostFunction* PointReprojectionFactorVI::Create(const PinholeIntrinsics& K,
                                                       const Eigen::Vector2d& uv,
                                                       const Eigen::Matrix2d& sqrt_information) {
  return new PointReprojectionFactorVI(MakePointObservation(K, uv, sqrt_information));
}

ceres::CostFunction* PointReprojectionFactorVI::CreateAutoDiff(
    const PinholeIntrinsics& K, const Eigen::Vector2d& uv,
    const Eigen::Matrix2d& sqrt_information) {
  return new ceres::AutoDiffCostFunction<PointReprojectionResidualVI, 2, 7, 7, 3>(
      new PointReprojectionResidualVI{{MakePointObservation(K, uv, sqrt_information)}});
}

bool PointReprojectionFactorVI::Evaluate(double const* const* parameters, double* residuals,
                                         double** jacobians) const {
  Eigen::Quaterniond q_wb, q_bc;
  Eigen::Matrix3d R_wb, R_bc;
  Eigen::Vector3d t_wb, t_bc;
  if (!pose_block::Read(parameters[0], &q_wb, &R_wb, &t_wb) ||
      !pose_block::Read(parameters[1], &q_bc, &R_bc, &t_bc) || !FinitePoint(parameters[2])) {
    return false;
  }
  const Eigen::Map<const Eigen::Vector3d> p_w(parameters[2]);
  // p_b = R_wb^T (p_w - t_wb),  p_c = R_bc^T (p_b - t_bc).
  const Eigen::Vector3d p_b = R_wb.transpose() * (p_w - t_wb);
  const Eigen::Vector3d p_c = R_bc.transpose() * (p_b - t_bc);
  const bool need_j = jacobians && (jacobians[0] || jacobians[1] || jacobians[2]);
  Eigen::Matrix<double, 2, 3> A;
  if (!WhitenedResidual(obs_, p_c, residuals, need_j ? &A : nullptr)) return false;
  if (!need_j) return true;
  // A = S d_uv/d_p_c, B = A R_bc^T = S d_uv/d_p_b.
  //   T_b_c:  d p_c/d dtheta_bc = [p_c]x,        d p_c/d dt_bc = -R_bc^T
  //   T_w_b:  d p_b/d dtheta_wb = [p_b]x,        d p_b/d dt_wb = -R_wb^T
  //   p_w:    d p_b/d p_w = R_wb^T
  const Eigen::Matrix<double, 2, 3> B = A * R_bc.transpose();
  const Eigen::Matrix<double, 2, 3> d_r_d_pw = B * R_wb.transpose();
  if (jacobians[0]) {
    pose_block::WriteAmbient<2>(B * Hat<double>(p_b), -d_r_d_pw, q_wb, jacobians[0]);
  }
  if (jacobians[1]) {
    pose_block::WriteAmbient<2>(A * Hat<double>(p_c), -B, q_bc, jacobians[1]);
  }
  if (jacobians[2]) {
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> J_pw(jacobians[2]);
    J_pw = d_r_d_pw;
  }
  return true;
}

}  // namespace plucker
