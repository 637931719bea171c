// Marginalization of estimation variables into a linear prior on the ones that remain (the
// sliding-window pattern of VINS-Mono; docs/math/marginalization.md).
//
// Given the residual blocks that touch the variables to remove, linearised at the current
// values (each block's tangent through its manifold's PlusJacobian, robust losses applied as
// Ceres does: sqrt(rho') scaling with the second-order correction):
//   H = J^T J,  g = J^T r  over the tangents of every block involved;
//   H* = H_kk - H_km H_mm^+ H_mk,  g* = g_k - H_km H_mm^+ g_m            (Schur complement)
// and the prior keeps them as a residual on the kept blocks k:
//   r_prior(x) = r_p + J_p Minus(x, x0),  J_p^T J_p = H*,  J_p^T r_p = g*
// (J_p = sqrt(Lambda) V^T from H* = V Lambda V^T, eigenvalues below `eigenvalue_floor` times
// the largest dropped; H_mm^+ the same pseudo-inverse). Minus is the block's manifold Minus, so
// ||r_prior||^2 / 2 = const + g*^T dx + dx^T H* dx / 2 for dx = Minus(x, x0).
//
// The linearisation point x0 of the kept blocks is frozen in the prior. An estimator must
// evaluate the other factors on those blocks at the same point for their Jacobians (first-estimate
// Jacobians) or accept the inconsistency; that policy belongs to the estimator.
//
// Supported block manifolds: none (Euclidean), PoseManifold, LineManifold (their Minus is
// Log(x0^-1 y) on the quaternion, a difference or an angle on the rest, whose derivative in y is
// exact: Jr^-1 on the rotation, identity on the rest).
#pragma once

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>

#include <Eigen/Core>
#include <vector>

namespace plucker {

struct MarginalizationBlock {
  double* values = nullptr;  // the block's storage, as given to Ceres
  int ambient_size = 0;
  const ceres::Manifold* manifold = nullptr;  // nullptr: Euclidean
};

struct MarginalizationResidual {
  const ceres::CostFunction* cost = nullptr;  // not owned
  const ceres::LossFunction* loss = nullptr;  // optional, not owned
  std::vector<double*> blocks;                // in the cost function's order
};

struct MarginalizationOptions {
  double eigenvalue_floor = 1e-10;  // relative to the largest eigenvalue
};

struct MarginalizationStatistics {
  int residual_blocks = 0;
  int marginalized_dimension = 0;  // tangent dimension removed
  int kept_dimension = 0;
  int prior_rank = 0;  // rows of J_p
};

class MarginalizationPrior {
 public:
  // Throws std::invalid_argument for a residual block that references an undeclared block, an
  // unsupported manifold, a marginalized block that no residual touches, or a residual or
  // Jacobian that cannot be evaluated (non-finite). Marginalizing every block that the residuals
  // touch gives an empty prior (no kept block, rank 0; the cost-function factories then throw
  // std::logic_error).
  static MarginalizationPrior Build(const std::vector<MarginalizationBlock>& blocks,
                                    const std::vector<MarginalizationResidual>& residuals,
                                    const std::vector<double*>& marginalize,
                                    const MarginalizationOptions& options = {});

  // The kept blocks (the prior's parameter blocks, in this order) and their frozen values x0.
  const std::vector<MarginalizationBlock>& KeptBlocks() const { return kept_; }
  const std::vector<std::vector<double>>& LinearisationPoint() const { return x0_; }
  const Eigen::MatrixXd& Jacobian() const { return J_; }  // J_p (rank x kept tangent dimension)
  const Eigen::VectorXd& Residual() const { return r_; }  // r_p
  const MarginalizationStatistics& Statistics() const { return stats_; }
  Eigen::MatrixXd Information() const { return J_.transpose() * J_; }  // H*
  Eigen::VectorXd Gradient() const { return J_.transpose() * r_; }     // g*

  // The prior as a cost function on KeptBlocks() (owned by the caller / problem) and its
  // autodiff twin (for the checks).
  ceres::CostFunction* CreateCostFunction() const;
  ceres::CostFunction* CreateAutoDiffCostFunction() const;

 private:
  std::vector<MarginalizationBlock> kept_;
  std::vector<std::vector<double>> x0_;
  Eigen::MatrixXd J_;
  Eigen::VectorXd r_;
  MarginalizationStatistics stats_;
};

}  // namespace plucker
