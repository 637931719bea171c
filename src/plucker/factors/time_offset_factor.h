// Visual-inertial factors with the camera-IMU time offset td (docs/math/time-offset.md).
//
// Convention (Kalibr): t_imu = t_cam + td. The window places the pose of a frame at its image
// stamp read on the IMU clock; the image was in fact taken td later on that clock. With the
// feature velocity model (the feature moves at the constant image velocity v [px/s] of its track
// around the frame), the feature at the pose's time is where it was td before the image:
//   uv(td) = uv - td v,
// and every endpoint of a segment likewise: p(td) = p - td v_p. IMU stamps that run 8 ms late
// give td = +0.008.
//
//   PointReprojectionFactorVITimeOffset  (2 | 7 T_w_b, 7 T_b_c, 1 td, 3 p_w):
//       r = S (pi(K, (T_w_b T_b_c)^-1 p_w) - uv(td)),   d r / d td = S v
//       (the other Jacobians are PointReprojectionFactorVI's: the measurement enters additively).
//   AnchoredLineFactorVITimeOffset       (2 | 7 T_w_b, 7 T_b_c, 1 td, 6 anchored line):
//       the AnchoredLineFactorVI residual with the endpoints s(td), e(td). The endpoint distance
//       n^T [p; 1] / |n_xy| is affine in the endpoint p, so with the verified factor evaluated at
//       the endpoints p (residual r_A, Jacobians J_A) and at p - tau v (r_B, J_B):
//         r(td) = (1 - td / tau) r_A + (td / tau) r_B,   J(td) = (1 - td / tau) J_A + (td / tau)
//         J_B, d r / d td = (r_B - r_A) / tau,
//       exact for any tau > 0 (tau = 1 s, shortened so that the shifted segment keeps at least
//       half its length).
// In both, T_b_c may be held (jacobians[1] == nullptr is honoured). Zero velocity gives the
// factors without time offset and a zero td column. td comes before the landmark so that the
// landmark is the last block, as in every visual factor of the window.
//
// Errors: Create/CreateAutoDiff throw std::invalid_argument as the factors without time offset,
// and for a non-finite velocity. Evaluate returns false where those do and for a non-finite td.
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <memory>

#include "plucker/factors/anchored_line_factor.h"
#include "plucker/factors/point_reprojection_factor.h"
#include "plucker/geometry/camera.h"

namespace plucker {

class PointReprojectionFactorVITimeOffset final : public ceres::SizedCostFunction<2, 7, 7, 1, 3> {
 public:
  static ceres::CostFunction* Create(const PinholeIntrinsics& K, const Eigen::Vector2d& uv,
                                     const Eigen::Vector2d& uv_velocity,
                                     const Eigen::Matrix2d& sqrt_information);
  static ceres::CostFunction* CreateAutoDiff(const PinholeIntrinsics& K, const Eigen::Vector2d& uv,
                                             const Eigen::Vector2d& uv_velocity,
                                             const Eigen::Matrix2d& sqrt_information);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  PointReprojectionFactorVITimeOffset(ceres::CostFunction* vi, const Eigen::Vector2d& S_v)
      : vi_(vi), S_v_(S_v) {}
  std::unique_ptr<ceres::CostFunction> vi_;  // PointReprojectionFactorVI at uv
  Eigen::Vector2d S_v_;                      // S v: the whitened velocity
};

class AnchoredLineFactorVITimeOffset final : public ceres::SizedCostFunction<2, 7, 7, 1, 6> {
 public:
  static ceres::CostFunction* Create(const PinholeIntrinsics& K, const Eigen::Vector2d& s_px,
                                     const Eigen::Vector2d& e_px, const Eigen::Vector2d& s_velocity,
                                     const Eigen::Vector2d& e_velocity,
                                     const Eigen::Matrix2d& sqrt_information,
                                     const LineAnchor& anchor);
  static ceres::CostFunction* CreateAutoDiff(
      const PinholeIntrinsics& K, const Eigen::Vector2d& s_px, const Eigen::Vector2d& e_px,
      const Eigen::Vector2d& s_velocity, const Eigen::Vector2d& e_velocity,
      const Eigen::Matrix2d& sqrt_information, const LineAnchor& anchor);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  AnchoredLineFactorVITimeOffset(ceres::CostFunction* at, ceres::CostFunction* shifted, double tau)
      : at_(at), shifted_(shifted), tau_(tau) {}
  std::unique_ptr<ceres::CostFunction> at_;       // AnchoredLineFactorVI at s, e
  std::unique_ptr<ceres::CostFunction> shifted_;  // ... at s - tau v_s, e - tau v_e
  double tau_;                                    // s
};

}  // namespace plucker
