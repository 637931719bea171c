#include "plucker/verify/lidar_comparison_factors.h"

#include "plucker/factors/pose_block.h"

namespace plucker {
namespace verify {

namespace {

constexpr char kEdge2[] = "PointToEdge2Factor";
constexpr char kEdgeScalar[] = "PointToEdgeScalarFactor";

lidar_comparison_residuals::PointToEdge2 MakeEdge2(const Eigen::Vector3d& p_s,
                                                   const Eigen::Vector3d& a_w,
                                                   const Eigen::Vector3d& b_w, double sigma) {
  const lidar_residuals::PointToEdge edge =
      lidar_residuals::MakePointToEdge(kEdge2, p_s, a_w, b_w, sigma);
  const Eigen::Vector3d& u = edge.u_w;
  // e1: the unit axis least aligned with u, made orthogonal to u; e2 = u x e1.
  Eigen::Index k;
  u.cwiseAbs().minCoeff(&k);
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();
  axis(k) = 1.0;
  const Eigen::Vector3d e1 = (axis - u.dot(axis) * u).normalized();
  const Eigen::Vector3d e2 = u.cross(e1);
  return {p_s, a_w, e1, e2, edge.inv_sigma};
}

}  // namespace

// ---------------------------------------------------------------- PointToEdge2Factor

PointToEdge2Factor::PointToEdge2Factor(const lidar_comparison_residuals::PointToEdge2& f)
    : p_s_(f.p_s) {
  E_scaled_.row(0) = f.e1_w.transpose() * f.inv_sigma;
  E_scaled_.row(1) = f.e2_w.transpose() * f.inv_sigma;
  offset_ = E_scaled_ * f.a_w;
}

ceres::CostFunction* PointToEdge2Factor::Create(const Eigen::Vector3d& p_s,
                                                const Eigen::Vector3d& a_w,
                                                const Eigen::Vector3d& b_w, double sigma) {
  return new PointToEdge2Factor(MakeEdge2(p_s, a_w, b_w, sigma));
}

ceres::CostFunction* PointToEdge2Factor::CreateAutoDiff(const Eigen::Vector3d& p_s,
                                                        const Eigen::Vector3d& a_w,
                                                        const Eigen::Vector3d& b_w, double sigma) {
  return new ceres::AutoDiffCostFunction<lidar_comparison_residuals::PointToEdge2, 2, 7>(
      new lidar_comparison_residuals::PointToEdge2(MakeEdge2(p_s, a_w, b_w, sigma)));
}

bool PointToEdge2Factor::Evaluate(double const* const* parameters, double* residuals,
                                  double** jacobians) const {
  Eigen::Quaterniond q;
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  if (!pose_block::Read(parameters[0], &q, &R, &t)) return false;
  // Row i: e_i.(R p + t - a) = (R^T e_i).p + e_i.t - e_i.a.
  const Eigen::Matrix<double, 2, 3> E_s = E_scaled_ * R;  // rows (R^T e_i)^T
  Eigen::Map<Eigen::Vector2d> r(residuals);
  r = E_s * p_s_ + E_scaled_ * t - offset_;
  if (jacobians && jacobians[0]) {
    Eigen::Matrix<double, 2, 3> J_rot;
    J_rot.row(0) = p_s_.cross(E_s.row(0).transpose()).transpose();
    J_rot.row(1) = p_s_.cross(E_s.row(1).transpose()).transpose();
    pose_block::WriteAmbient<2>(J_rot, E_scaled_, q, jacobians[0]);
  }
  return true;
}

// ---------------------------------------------------------------- PointToEdgeScalarFactor

PointToEdgeScalarFactor::PointToEdgeScalarFactor(const lidar_residuals::PointToEdge& f)
    : p_s_(f.p_s), u_w_(f.u_w), a_w_(f.a_w), inv_sigma_(f.inv_sigma) {}

ceres::CostFunction* PointToEdgeScalarFactor::Create(const Eigen::Vector3d& p_s,
                                                     const Eigen::Vector3d& a_w,
                                                     const Eigen::Vector3d& b_w, double sigma) {
  return new PointToEdgeScalarFactor(
      lidar_residuals::MakePointToEdge(kEdgeScalar, p_s, a_w, b_w, sigma));
}

ceres::CostFunction* PointToEdgeScalarFactor::CreateAutoDiff(const Eigen::Vector3d& p_s,
                                                             const Eigen::Vector3d& a_w,
                                                             const Eigen::Vector3d& b_w,
                                                             double sigma) {
  return new ceres::AutoDiffCostFunction<lidar_comparison_residuals::PointToEdgeScalar, 1, 7>(
      new lidar_comparison_residuals::PointToEdgeScalar{
          lidar_residuals::MakePointToEdge(kEdgeScalar, p_s, a_w, b_w, sigma)});
}

bool PointToEdgeScalarFactor::Evaluate(double const* const* parameters, double* residuals,
                                       double** jacobians) const {
  Eigen::Quaterniond q;
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  if (!pose_block::Read(parameters[0], &q, &R, &t)) return false;
  const Eigen::Vector3d Y = u_w_.cross(R * p_s_ + t - a_w_);
  const double distance = Y.norm();
  residuals[0] = distance * inv_sigma_;
  if (jacobians && jacobians[0]) {
    Eigen::Map<Eigen::Matrix<double, 1, 7, Eigen::RowMajor>> J(jacobians[0]);
    if (!(distance > 0.0)) {
      J.setZero();  // the subgradient 0 at the kink (see the header)
      return true;
    }
    // d|Y|/d p_w = (Y/|Y|)^T [u]x = ((Y x u)/|Y|)^T =: g^T; then as the plane with normal g.
    const Eigen::Vector3d g = Y.cross(u_w_) * (inv_sigma_ / distance);
    const Eigen::Vector3d g_s = R.transpose() * g;
    const Eigen::Matrix<double, 1, 3> J_rot = p_s_.cross(g_s).transpose();
    pose_block::WriteAmbient<1>(J_rot, g.transpose(), q, jacobians[0]);
  }
  return true;
}

}  // namespace verify
}  // namespace plucker
