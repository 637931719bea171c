#include "plucker/factors/lidar_factors.h"

#include "plucker/factors/pose_block.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace plucker {

namespace {

bool Finite(const Eigen::Vector3d& v) { return v.allFinite(); }

void Require(bool ok, const char* factor, const char* what) {  // no string unless it throws
  if (!ok) throw std::invalid_argument(std::string(factor) + ": " + what);
}

double CheckSigma(const char* factor, double sigma) {
  Require(std::isfinite(sigma) && sigma > 0.0 && std::isfinite(1.0 / sigma), factor,
          "sigma must be finite and > 0");
  return 1.0 / sigma;
}

// Validated unit direction u = (a - b)/|a - b| of an edge.
Eigen::Vector3d EdgeDirection(const char* factor, const Eigen::Vector3d& p_s,
                              const Eigen::Vector3d& a_w, const Eigen::Vector3d& b_w) {
  Require(Finite(p_s) && Finite(a_w) && Finite(b_w), factor, "non-finite point");
  const double length = (a_w - b_w).norm();
  const double scale = 1.0 + std::max(a_w.norm(), b_w.norm());
  Require(std::isfinite(length), factor, "edge points too far apart (overflow)");
  Require(length > 1e-12 * scale, factor, "edge points a and b coincide");
  return (a_w - b_w) / length;
}

constexpr char kPlane[] = "PointToPlaneFactor";
constexpr char kEdge[] = "PointToEdgeFactor";

lidar_residuals::PointToPlane MakePlane(const Eigen::Vector3d& p_s, const Eigen::Vector3d& m_w,
                                        const Eigen::Vector3d& q_w, double sigma) {
  Require(Finite(p_s) && Finite(m_w) && Finite(q_w), kPlane, "non-finite input");
  Require(std::abs(m_w.norm() - 1.0) <= 1e-6, kPlane, "the plane normal must be a unit vector");
  return {p_s, m_w.normalized(), q_w, CheckSigma(kPlane, sigma)};
}

lidar_residuals::PointToEdge MakeEdgeFromDirection(const char* name, const Eigen::Vector3d& p_s,
                                                   const Eigen::Vector3d& a_w,
                                                   const Eigen::Vector3d& u_w, double sigma) {
  Require(Finite(p_s) && Finite(a_w) && Finite(u_w), name, "non-finite input");
  Require(std::abs(u_w.norm() - 1.0) <= 1e-6, name, "the edge direction must be a unit vector");
  return {p_s, a_w, u_w.normalized(), CheckSigma(name, sigma)};
}

}  // namespace

lidar_residuals::PointToEdge lidar_residuals::MakePointToEdge(const char* factor,
                                                              const Eigen::Vector3d& p_s,
                                                              const Eigen::Vector3d& a_w,
                                                              const Eigen::Vector3d& b_w,
                                                              double sigma) {
  const Eigen::Vector3d u = EdgeDirection(factor, p_s, a_w, b_w);
  return {p_s, a_w, u, CheckSigma(factor, sigma)};
}

PlaneResidual PlaneResidual::Create(const Eigen::Vector3d& p_s, const Eigen::Vector3d& m_w,
                                    const Eigen::Vector3d& q_w, double sigma) {
  const lidar_residuals::PointToPlane f = MakePlane(p_s, m_w, q_w, sigma);
  return {f.p_s, f.m_w * f.inv_sigma, f.m_w.dot(f.q_w) * f.inv_sigma};
}

EdgeResidual EdgeResidual::CreateFromDirection(const Eigen::Vector3d& p_s,
                                               const Eigen::Vector3d& a_w,
                                               const Eigen::Vector3d& u_w, double sigma) {
  const lidar_residuals::PointToEdge f = MakeEdgeFromDirection(kEdge, p_s, a_w, u_w, sigma);
  return {f.p_s, f.u_w * f.inv_sigma, f.a_w};
}

// ---------------------------------------------------------------- PointToPlaneFactor

ceres::CostFunction* PointToPlaneFactor::Create(const Eigen::Vector3d& p_s,
                                                const Eigen::Vector3d& m_w,
                                                const Eigen::Vector3d& q_w, double sigma) {
  return new PointToPlaneFactor(PlaneResidual::Create(p_s, m_w, q_w, sigma));
}

ceres::CostFunction* PointToPlaneFactor::CreateAutoDiff(const Eigen::Vector3d& p_s,
                                                        const Eigen::Vector3d& m_w,
                                                        const Eigen::Vector3d& q_w, double sigma) {
  return new ceres::AutoDiffCostFunction<lidar_residuals::PointToPlane, 1, 7>(
      new lidar_residuals::PointToPlane(MakePlane(p_s, m_w, q_w, sigma)));
}

bool PointToPlaneFactor::Evaluate(double const* const* parameters, double* residuals,
                                  double** jacobians) const {
  Eigen::Quaterniond q;
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  if (!pose_block::Read(parameters[0], &q, &R, &t)) return false;
  Eigen::Matrix<double, 1, 6> J;
  const bool with_jacobian = jacobians && jacobians[0];
  residuals[0] = r_.Evaluate(R, t, with_jacobian ? &J : nullptr);
  if (with_jacobian)
    pose_block::WriteAmbient<1>(J.leftCols<3>(), J.rightCols<3>(), q, jacobians[0]);
  return true;
}

// ---------------------------------------------------------------- PointToEdgeFactor

ceres::CostFunction* PointToEdgeFactor::Create(const Eigen::Vector3d& p_s,
                                               const Eigen::Vector3d& a_w,
                                               const Eigen::Vector3d& b_w, double sigma) {
  const lidar_residuals::PointToEdge f =
      lidar_residuals::MakePointToEdge(kEdge, p_s, a_w, b_w, sigma);
  return new PointToEdgeFactor({f.p_s, f.u_w * f.inv_sigma, f.a_w});
}

ceres::CostFunction* PointToEdgeFactor::CreateFromDirection(const Eigen::Vector3d& p_s,
                                                            const Eigen::Vector3d& a_w,
                                                            const Eigen::Vector3d& u_w,
                                                            double sigma) {
  return new PointToEdgeFactor(EdgeResidual::CreateFromDirection(p_s, a_w, u_w, sigma));
}

ceres::CostFunction* PointToEdgeFactor::CreateAutoDiff(const Eigen::Vector3d& p_s,
                                                       const Eigen::Vector3d& a_w,
                                                       const Eigen::Vector3d& b_w, double sigma) {
  return new ceres::AutoDiffCostFunction<lidar_residuals::PointToEdge, 3, 7>(
      new lidar_residuals::PointToEdge(
          lidar_residuals::MakePointToEdge(kEdge, p_s, a_w, b_w, sigma)));
}

bool PointToEdgeFactor::Evaluate(double const* const* parameters, double* residuals,
                                 double** jacobians) const {
  Eigen::Quaterniond q;
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  if (!pose_block::Read(parameters[0], &q, &R, &t)) return false;
  Eigen::Matrix<double, 3, 6> J;
  const bool with_jacobian = jacobians && jacobians[0];
  Eigen::Vector3d::Map(residuals) = r_.Evaluate(R, t, with_jacobian ? &J : nullptr);
  if (with_jacobian)
    pose_block::WriteAmbient<3>(J.leftCols<3>(), J.rightCols<3>(), q, jacobians[0]);
  return true;
}

}  // namespace plucker
