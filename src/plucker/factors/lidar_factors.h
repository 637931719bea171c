// LOAM-style LiDAR residuals on a scan pose T_w_s (7-value pose block [qx qy qz qw tx ty tz],
// PoseManifold, tangent (dtheta, dt) with R <- R Exp(dtheta), t <- t + dt).
//
// A scan point p_s is mapped to the world by p_w = R p_s + t. The residuals (docs/math/
// lidar-and-point-factors.md derives each Jacobian), with u = (a - b)/|a - b| the unit direction
// of the edge through a and b, and Y = (p_w - b) x (p_w - a)/|a - b| = u x (p_w - a):
//
//   factor               rows  residual r                       sigma |r|
//   PointToPlaneFactor   1     m_w . (p_w - q_w) / sigma        signed distance
//   PointToEdgeFactor    3     Y / sigma                        distance
//
// The comparison-only edge forms (2 rows E (p_w - a) / sigma, and LOAM's scalar |Y| / sigma)
// are in verify/lidar_comparison_factors.h (checked and benchmarked, not installed).
//
// Jacobians are written w.r.t. the AMBIENT 7 parameters: J_ambient = J_tangent * MinusJacobian(x)
// (pose_block::WriteAmbient; the exact derivative of the same residual with the quaternion
// normalised). Every Create() has a CreateAutoDiff() twin (ceres::AutoDiffCostFunction over the
// templated functors below, which normalise the quaternion) used as the test reference and the
// benchmark baseline.
//
// Construction errors: Create/CreateAutoDiff throw std::invalid_argument for non-finite inputs,
// a == b (|a - b| <= 1e-12 (1 + max(|a|, |b|))), a normal whose norm is not within 1e-6 of one
// (it is then re-normalised exactly), and sigma <= 0 or non-finite.
// Evaluate returns false for non-finite parameters (including a zero quaternion).
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace plucker {

// Templated residual functors (the autodiff twins). Each normalises the quaternion.
namespace lidar_residuals {

template <typename T>
Eigen::Matrix<T, 3, 1> ScanPointToWorld(const T* pose, const Eigen::Vector3d& p_s) {
  Eigen::Quaternion<T> q(pose[3], pose[0], pose[1], pose[2]);
  q.normalize();
  return q * p_s.cast<T>() + Eigen::Matrix<T, 3, 1>(pose[4], pose[5], pose[6]);
}

struct PointToPlane {
  Eigen::Vector3d p_s, m_w, q_w;
  double inv_sigma;
  template <typename T>
  bool operator()(const T* pose, T* r) const {
    const Eigen::Matrix<T, 3, 1> p_w = ScanPointToWorld(pose, p_s);
    r[0] = m_w.cast<T>().dot(p_w - q_w.cast<T>()) * T(inv_sigma);
    return true;
  }
};

struct PointToEdge {
  Eigen::Vector3d p_s, a_w, u_w;  // u_w = (a - b)/|a - b|
  double inv_sigma;
  template <typename T>
  bool operator()(const T* pose, T* r) const {
    const Eigen::Matrix<T, 3, 1> p_w = ScanPointToWorld(pose, p_s);
    const Eigen::Matrix<T, 3, 1> Y = u_w.cast<T>().cross(p_w - a_w.cast<T>());
    for (int i = 0; i < 3; ++i) r[i] = Y(i) * T(inv_sigma);
    return true;
  }
};

// The validated data of a two-point edge residual: the checks of the edge Create() functions
// (see the top of the file), throwing std::invalid_argument whose message starts with `factor`.
PointToEdge MakePointToEdge(const char* factor, const Eigen::Vector3d& p_s,
                            const Eigen::Vector3d& a_w, const Eigen::Vector3d& b_w, double sigma);

}  // namespace lidar_residuals

// r = m_w . (p_w - q_w) / sigma; the signed point-to-plane distance in units of sigma.
class PointToPlaneFactor : public ceres::SizedCostFunction<1, 7> {
 public:
  // m_w: unit normal (|m| within 1e-6 of 1), q_w: any point on the plane, sigma > 0 [m].
  static ceres::CostFunction* Create(const Eigen::Vector3d& p_s, const Eigen::Vector3d& m_w,
                                     const Eigen::Vector3d& q_w, double sigma = 1.0);
  static ceres::CostFunction* CreateAutoDiff(const Eigen::Vector3d& p_s, const Eigen::Vector3d& m_w,
                                             const Eigen::Vector3d& q_w, double sigma = 1.0);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  explicit PointToPlaneFactor(const lidar_residuals::PointToPlane& f);
  Eigen::Vector3d p_s_, m_scaled_;  // m_scaled = m / sigma
  double offset_;                   // m . q / sigma
};

// r = Y / sigma with Y = (p_w - b) x (p_w - a)/|a - b| = u x (p_w - a); |r| = distance / sigma.
// Smooth everywhere (linear in p_w), also on the line itself.
class PointToEdgeFactor : public ceres::SizedCostFunction<3, 7> {
 public:
  static ceres::CostFunction* Create(const Eigen::Vector3d& p_s, const Eigen::Vector3d& a_w,
                                     const Eigen::Vector3d& b_w, double sigma = 1.0);
  static ceres::CostFunction* CreateAutoDiff(const Eigen::Vector3d& p_s, const Eigen::Vector3d& a_w,
                                             const Eigen::Vector3d& b_w, double sigma = 1.0);
  // The same residual for the line through a_w with unit direction u_w (|u| within 1e-6 of 1,
  // re-normalised), as a local line fit gives it.
  static ceres::CostFunction* CreateFromDirection(const Eigen::Vector3d& p_s,
                                                  const Eigen::Vector3d& a_w,
                                                  const Eigen::Vector3d& u_w, double sigma = 1.0);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  explicit PointToEdgeFactor(const lidar_residuals::PointToEdge& f);
  Eigen::Vector3d p_s_, u_scaled_, a_w_;  // u_scaled = u / sigma
};

}  // namespace plucker
