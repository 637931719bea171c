// Comparison-only edge residuals on a scan pose T_w_s, beside the installed PointToEdgeFactor
// (factors/lidar_factors.h, same pose block, conventions and construction errors). They exist to
// be checked (`plucker check-jacobians`, factor.lidar.*) and benchmarked (`plucker bench factors`)
// against the smooth 3-row edge residual; the odometry does not use them. Not installed.
//
//   factor                   rows  residual r                                sigma |r|
//   PointToEdge2Factor       2     E (p_w - a) / sigma, E = [e1^T; e2^T]     distance
//                                  (e1, e2 orthonormal, orthogonal to u)
//   PointToEdgeScalarFactor  1     |Y| / sigma (classic LOAM: kink at zero   distance
//                                  distance), Y = u x (p_w - a)
//
// Scalar edge at zero distance: |Y| is not differentiable at Y = 0. Evaluate returns residual 0
// and a ZERO Jacobian there (0 is in the subdifferential of |.| at 0, so it is a valid
// subgradient), never NaN. Such a residual gives Gauss-Newton no information at the very
// configuration every converged correspondence approaches, which is why the smooth vector forms
// are preferred.
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "plucker/factors/lidar_factors.h"

namespace plucker {
namespace verify {

// The autodiff twins (templated functors; each normalises the quaternion).
namespace lidar_comparison_residuals {

struct PointToEdge2 {
  Eigen::Vector3d p_s, a_w, e1_w, e2_w;
  double inv_sigma;
  template <typename T>
  bool operator()(const T* pose, T* r) const {
    const Eigen::Matrix<T, 3, 1> v = lidar_residuals::ScanPointToWorld(pose, p_s) - a_w.cast<T>();
    r[0] = e1_w.cast<T>().dot(v) * T(inv_sigma);
    r[1] = e2_w.cast<T>().dot(v) * T(inv_sigma);
    return true;
  }
};

struct PointToEdgeScalar {
  lidar_residuals::PointToEdge edge;
  template <typename T>
  bool operator()(const T* pose, T* r) const {
    using std::sqrt;
    T Y[3];
    if (!edge(pose, Y)) return false;  // u x (p_w - a) / sigma
    const T sq = Y[0] * Y[0] + Y[1] * Y[1] + Y[2] * Y[2];
    // sqrt'(0) is infinite: return 0 with a zero derivative, as the analytic version does.
    r[0] = sq > T(0) ? T(sqrt(sq)) : T(0);
    return true;
  }
};

}  // namespace lidar_comparison_residuals

// r = [e1 . (p_w - a), e2 . (p_w - a)] / sigma: the minimal (2-dof) smooth edge residual.
class PointToEdge2Factor : public ceres::SizedCostFunction<2, 7> {
 public:
  static ceres::CostFunction* Create(const Eigen::Vector3d& p_s, const Eigen::Vector3d& a_w,
                                     const Eigen::Vector3d& b_w, double sigma = 1.0);
  static ceres::CostFunction* CreateAutoDiff(const Eigen::Vector3d& p_s, const Eigen::Vector3d& a_w,
                                             const Eigen::Vector3d& b_w, double sigma = 1.0);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  explicit PointToEdge2Factor(const lidar_comparison_residuals::PointToEdge2& f);
  Eigen::Vector3d p_s_;
  Eigen::Matrix<double, 2, 3> E_scaled_;  // rows e1, e2 divided by sigma
  Eigen::Vector2d offset_;                // E_scaled a
};

// r = |Y| / sigma (classic LOAM). Zero distance: residual 0, zero Jacobian (see top of file).
class PointToEdgeScalarFactor : public ceres::SizedCostFunction<1, 7> {
 public:
  static ceres::CostFunction* Create(const Eigen::Vector3d& p_s, const Eigen::Vector3d& a_w,
                                     const Eigen::Vector3d& b_w, double sigma = 1.0);
  static ceres::CostFunction* CreateAutoDiff(const Eigen::Vector3d& p_s, const Eigen::Vector3d& a_w,
                                             const Eigen::Vector3d& b_w, double sigma = 1.0);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  explicit PointToEdgeScalarFactor(const lidar_residuals::PointToEdge& f);
  Eigen::Vector3d p_s_, u_w_, a_w_;
  double inv_sigma_;
};

}  // namespace verify
}  // namespace plucker
