#include "plucker/factors/lidar_factors.h"

#include "plucker/factors/pose_block.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace plucker {

namespace {

bool Finite(const Eigen::Vector3d& v) { return v.allFinite(); }

void Require(bool ok, const char* factor, const std::string& what) {
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

// ---------------------------------------------------------------- PointToPlaneFactor

PointToPlaneFactor::PointToPlaneFactor(const lidar_residuals::PointToPlane& f)
    : p_s_(f.p_s), m_scaled_(f.m_w * f.inv_sigma), offset_(f.m_w.dot(f.q_w) * f.inv_sigma) {}

ceres::CostFunction* PointToPlaneFactor::Create(const Eigen::Vector3d& p_s,
                                                const Eigen::Vector3d& m_w,
                                                const Eigen::Vector3d& q_w, double sigma) {
  return new PointToPlaneFactor(MakePlane(p_s, m_w, q_w, sigma));
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
  // r = m.(R p + t) - m.q = (R^T m).p + m.t - m.q  (m already divided by sigma).
  const Eigen::Vector3d m_s = R.transpose() * m_scaled_;
  residuals[0] = m_s.dot(p_s_) + m_scaled_.dot(t) - offset_;
  if (jacobians && jacobians[0]) {
    // d r/d dtheta = -m^T R [p]x = (p x R^T m)^T;  d r/d dt = m^T.
    const Eigen::Matrix<double, 1, 3> J_rot = p_s_.cross(m_s).transpose();
    pose_block::WriteAmbient<1>(J_rot, m_scaled_.transpose(), q, jacobians[0]);
  }
  return true;
}

// ---------------------------------------------------------------- PointToEdgeFactor

PointToEdgeFactor::PointToEdgeFactor(const lidar_residuals::PointToEdge& f)
    : p_s_(f.p_s), u_scaled_(f.u_w * f.inv_sigma), a_w_(f.a_w) {}

ceres::CostFunction* PointToEdgeFactor::Create(const Eigen::Vector3d& p_s,
                                               const Eigen::Vector3d& a_w,
                                               const Eigen::Vector3d& b_w, double sigma) {
  return new PointToEdgeFactor(lidar_residuals::MakePointToEdge(kEdge, p_s, a_w, b_w, sigma));
}

ceres::CostFunction* PointToEdgeFactor::CreateFromDirection(const Eigen::Vector3d& p_s,
                                                            const Eigen::Vector3d& a_w,
                                                            const Eigen::Vector3d& u_w,
                                                            double sigma) {
  return new PointToEdgeFactor(MakeEdgeFromDirection(kEdge, p_s, a_w, u_w, sigma));
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
  const Eigen::Vector3d Rp = R * p_s_;
  Eigen::Map<Eigen::Vector3d> r(residuals);
  r = u_scaled_.cross(Rp + t - a_w_);
  if (jacobians && jacobians[0]) {
    // d r/d p_w = [u]x;  d r/d dtheta = -[u]x R [p]x = -R [R^T u]x [p]x
    //   = (R^T u . p) R - (R p)(R^T u)^T;   d r/d dt = [u]x.
    const Eigen::Vector3d u_s = R.transpose() * u_scaled_;
    const Eigen::Matrix3d J_rot = u_s.dot(p_s_) * R - Rp * u_s.transpose();
    Eigen::Matrix3d J_t;
    J_t << 0.0, -u_scaled_.z(), u_scaled_.y(), u_scaled_.z(), 0.0, -u_scaled_.x(), -u_scaled_.y(),
        u_scaled_.x(), 0.0;
    pose_block::WriteAmbient<3>(J_rot, J_t, q, jacobians[0]);
  }
  return true;
}

}  // namespace plucker
