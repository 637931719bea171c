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

// The residuals of the two factors below as values, with their tangent Jacobians d r/d(dtheta,
// dt) at (R_w_s, t_w_s): the one place these Jacobians are written. The factors' Evaluate turns
// them into ambient ones (pose_block::WriteAmbient); the LiDAR pose solver (lidar/pose_solver.h)
// sums them straight into its 6x6 normal equations, with no cost function per correspondence.
// Create() validates as the factors' Create() does (same errors).
struct PlaneResidual {
  Eigen::Vector3d p_s, m_scaled;  // m_scaled = m_w / sigma
  double offset;                  // m_w . q_w / sigma
  static PlaneResidual Create(const Eigen::Vector3d& p_s, const Eigen::Vector3d& m_w,
                              const Eigen::Vector3d& q_w, double sigma);
  // r = m.(R p + t) - m.q = (R^T m).p + m.t - m.q;  d r/d dtheta = -m^T R [p]x = (p x R^T m)^T,
  // d r/d dt = m^T.
  double Evaluate(const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                  Eigen::Matrix<double, 1, 6>* J) const {
    const Eigen::Vector3d m_s = R.transpose() * m_scaled;
    if (J) *J << p_s.cross(m_s).transpose(), m_scaled.transpose();
    return m_s.dot(p_s) + m_scaled.dot(t) - offset;
  }
};

struct EdgeResidual {
  Eigen::Vector3d p_s, u_scaled, a_w;  // u_scaled = u_w / sigma
  static EdgeResidual CreateFromDirection(const Eigen::Vector3d& p_s, const Eigen::Vector3d& a_w,
                                          const Eigen::Vector3d& u_w, double sigma);
  // r = u x (R p + t - a);  d r/d p_w = [u]x;  d r/d dtheta = -[u]x R [p]x = -R [R^T u]x [p]x
  //   = (R^T u . p) R - (R p)(R^T u)^T;  d r/d dt = [u]x.
  Eigen::Vector3d Evaluate(const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                           Eigen::Matrix<double, 3, 6>* J) const {
    const Eigen::Vector3d Rp = R * p_s;
    if (J) {
      const Eigen::Vector3d u_s = R.transpose() * u_scaled;
      const Eigen::Vector3d& u = u_scaled;
      J->leftCols<3>() = u_s.dot(p_s) * R - Rp * u_s.transpose();
      J->rightCols<3>() << 0.0, -u.z(), u.y(), u.z(), 0.0, -u.x(), -u.y(), u.x(), 0.0;
    }
    return u_scaled.cross(Rp + t - a_w);
  }
};

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
  explicit PointToPlaneFactor(const PlaneResidual& r) : r_(r) {}
  PlaneResidual r_;
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
  explicit PointToEdgeFactor(const EdgeResidual& r) : r_(r) {}
  EdgeResidual r_;
};

}  // namespace plucker
