#include "plucker/window/frame_tracker.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "plucker/factors/pose_manifold.h"
#include "plucker/factors/robust_loss.h"

namespace plucker {
namespace window {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using RowMajor2x7 = Eigen::Matrix<double, 2, 7, Eigen::RowMajor>;
using RowMajor7x6 = Eigen::Matrix<double, 7, 6, Eigen::RowMajor>;
using RowMajor6x7 = Eigen::Matrix<double, 6, 7, Eigen::RowMajor>;

bool IsPoseOnly(const PoseTerm& t) { return t.landmark == nullptr; }

void CheckTerms(const std::vector<PoseTerm>& terms) {
  for (const PoseTerm& t : terms) {
    const bool observation =
        t.cost != nullptr && t.landmark != nullptr && t.cost->num_residuals() == 2 &&
        t.cost->parameter_block_sizes().size() == 2 && t.cost->parameter_block_sizes()[0] == 7;
    const bool pose_only =
        t.cost != nullptr && t.landmark == nullptr && t.cost->num_residuals() == 6 &&
        t.cost->parameter_block_sizes().size() == 1 && t.cost->parameter_block_sizes()[0] == 7;
    if (!observation && !pose_only) {
      throw std::invalid_argument(
          "RefinePose: a term needs a cost with 2 residuals on (7-value pose, landmark) and a "
          "landmark, or a cost with 6 residuals on the 7-value pose alone and no landmark");
    }
  }
}

// The Gauss-Newton system H = J^T J, g = J^T r of the robustified residuals in the tangent at
// `pose` (Ceres' Corrector: J <- sqrt(rho') (I - alpha r r^T / s) J, r <- sqrt(rho') / (1 -
// alpha) r; pose-only terms without the loss). False when a term cannot be evaluated.
bool Linearize(const std::vector<PoseTerm>& terms, const ceres::LossFunction* loss,
               const double* pose, Matrix6d* H, Vector6d* g, double* cost) {
  RowMajor7x6 plus;
  if (!PoseManifold().PlusJacobian(pose, plus.data())) return false;
  H->setZero();
  g->setZero();
  *cost = 0.0;
  Eigen::Vector2d r;
  RowMajor2x7 J_ambient;
  for (const PoseTerm& t : terms) {
    if (IsPoseOnly(t)) {
      Vector6d r6;
      RowMajor6x7 J6_ambient;
      const double* parameters[1] = {pose};
      double* jacobians[1] = {J6_ambient.data()};
      if (!t.cost->Evaluate(parameters, r6.data(), jacobians) || !r6.allFinite() ||
          !J6_ambient.allFinite()) {
        return false;
      }
      const Matrix6d J6 = J6_ambient * plus;
      *cost += 0.5 * r6.squaredNorm();
      H->noalias() += J6.transpose() * J6;
      g->noalias() += J6.transpose() * r6;
      continue;
    }
    const double* parameters[2] = {pose, t.landmark};
    double* jacobians[2] = {J_ambient.data(), nullptr};
    if (!t.cost->Evaluate(parameters, r.data(), jacobians) || !r.allFinite() ||
        !J_ambient.allFinite()) {
      return false;
    }
    Eigen::Matrix<double, 2, 6> J = J_ambient * plus;
    *cost += 0.5 * (loss == nullptr ? r.squaredNorm() : ApplyRobustLoss(*loss, r, J));
    H->noalias() += J.transpose() * J;
    g->noalias() += J.transpose() * r;
  }
  return true;
}

}  // namespace

PoseRefinementSummary RefinePose(const std::vector<PoseTerm>& terms,
                                 const ceres::LossFunction* loss,
                                 const PoseRefinementOptions& options, double* pose) {
  CheckTerms(terms);
  PoseRefinementSummary summary;
  const PoseManifold manifold;
  Matrix6d H;
  Vector6d g;
  double cost = 0.0;
  if (!Linearize(terms, loss, pose, &H, &g, &cost)) return summary;
  summary.ok = true;
  summary.initial_cost = summary.final_cost = cost;
  double radius = options.initial_trust_region_radius;
  double decrease_factor = 2.0;
  const Eigen::Map<const Eigen::Matrix<double, 7, 1>> x(pose);
  while (summary.iterations < options.max_iterations) {
    if (g.lpNorm<Eigen::Infinity>() <= options.gradient_tolerance) break;
    ++summary.iterations;
    // (H + D / radius) dx = -g, D = diag(H) in Ceres' Jacobi-scaled columns, clamped.
    const Vector6d scale =
        (Vector6d::Ones() + H.diagonal().cwiseMax(0.0).cwiseSqrt()).cwiseInverse();
    Matrix6d A = scale.asDiagonal() * H * scale.asDiagonal();
    A.diagonal() += A.diagonal().cwiseMax(1e-6).cwiseMin(1e32) / radius;
    const Vector6d rhs = -scale.cwiseProduct(g);
    const Vector6d dx = scale.cwiseProduct(A.ldlt().solve(rhs));
    // The candidate is linearised at once (nearly every step is accepted): its cost and, when
    // accepted, the next system.
    double candidate[7];
    double candidate_cost = std::numeric_limits<double>::infinity();
    Matrix6d H_candidate;
    Vector6d g_candidate;
    if (dx.allFinite() && manifold.Plus(pose, dx.data(), candidate)) {
      const double step_norm =
          (Eigen::Map<const Eigen::Matrix<double, 7, 1>>(candidate) - x).norm();
      if (step_norm <= options.parameter_tolerance * (x.norm() + options.parameter_tolerance)) {
        break;
      }
      if (!Linearize(terms, loss, candidate, &H_candidate, &g_candidate, &candidate_cost)) {
        candidate_cost = std::numeric_limits<double>::infinity();
      }
    }
    const double model_decrease = -(g.dot(dx) + 0.5 * dx.dot(H * dx));
    const double ratio = (cost - candidate_cost) / model_decrease;
    // Ceres stops at the function tolerance without taking the candidate (so does this: the
    // tracked poses then equal Ceres' to ~1e-8 m).
    const bool converged = std::isfinite(candidate_cost) &&
                           std::abs(cost - candidate_cost) <= options.function_tolerance * cost;
    if (converged) break;
    if (std::isfinite(candidate_cost) && model_decrease > 0.0 &&
        ratio > options.min_relative_decrease) {
      std::copy(candidate, candidate + 7, pose);
      H = H_candidate;
      g = g_candidate;
      cost = summary.final_cost = candidate_cost;
      radius = std::min(1e16, radius / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * ratio - 1.0, 3)));
      decrease_factor = 2.0;
    } else {
      radius /= decrease_factor;
      decrease_factor *= 2.0;
    }
    if (radius < 1e-32) break;
  }
  return summary;
}

}  // namespace window
}  // namespace plucker
