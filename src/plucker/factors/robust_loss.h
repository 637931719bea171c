// Ceres' robust-loss correction of one residual block (its internal Corrector), for code that
// forms normal equations itself: with s = |r|^2 and rho = loss(s), the corrected r and J give
// J^T J and J^T r of the second-order model of rho(|r(x)|^2) / 2 (Triggs et al., "Bundle
// adjustment: a modern synthesis", section 6.1), as Ceres' solvers see them. And the one robust
// loss choice of the estimators (window and LiDAR odometry) with the Ceres loss made from it.
#pragma once

#include <ceres/loss_function.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <memory>

namespace plucker {
namespace factors {

enum class RobustLoss { kNone, kHuber, kCauchy };

// The Ceres loss rho(s) of `loss` with its parameter `scale` (in the residual's units); nullptr
// for kNone (Ceres' trivial loss).
inline std::unique_ptr<ceres::LossFunction> MakeLossFunction(RobustLoss loss, double scale) {
  if (loss == RobustLoss::kHuber) return std::make_unique<ceres::HuberLoss>(scale);
  if (loss == RobustLoss::kCauchy) return std::make_unique<ceres::CauchyLoss>(scale);
  return nullptr;
}

}  // namespace factors

// Corrects r (m x 1) and J (m x n) in place; returns rho(|r|^2), the block's cost times two.
template <typename ResidualT, typename JacobianT>
double ApplyRobustLoss(const ceres::LossFunction& loss, Eigen::MatrixBase<ResidualT>& r,
                       Eigen::MatrixBase<JacobianT>& J) {
  const double s = r.squaredNorm();
  double rho[3];
  loss.Evaluate(s, rho);
  const double sqrt_rho1 = std::sqrt(std::max(rho[1], 0.0));
  if (s == 0.0 || rho[2] <= 0.0) {
    r *= sqrt_rho1;
    J *= sqrt_rho1;
    return rho[0];
  }
  const double alpha = 1.0 - std::sqrt(std::max(0.0, 1.0 + 2.0 * s * rho[2] / rho[1]));
  J = sqrt_rho1 * (J - (alpha / s) * r * (r.transpose() * J));
  r *= sqrt_rho1 / (1.0 - alpha);
  return rho[0];
}

}  // namespace plucker
