#include "plucker/lidar/pose_solver.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "plucker/factors/pose_manifold.h"

namespace plucker {
namespace lidar {
namespace {

constexpr int kMaxRows = 8;  // largest residual block of the LiDAR factors is 3

struct Linearisation {
  double cost = 0.0;
  Matrix6d H = Matrix6d::Zero();
  Vector6d g = Vector6d::Zero();
};

double Rho(const ceres::LossFunction* loss, double s, double* weight) {
  if (loss == nullptr) {
    if (weight) *weight = 1.0;
    return s;
  }
  double rho[3];
  loss->Evaluate(s, rho);
  if (weight) *weight = rho[1];
  return rho[0];
}

// Cost at T, and (when lin != nullptr) the reweighted normal equations. False on a failed or
// non-finite evaluation.
bool Evaluate(const std::vector<std::unique_ptr<ceres::CostFunction>>& residuals,
              const ceres::LossFunction* loss, const SE3d& T, double* cost, Linearisation* lin) {
  if (lin) *lin = Linearisation();
  double x[7];
  T.ToParameters(x);
  const double* parameters[1] = {x};
  Eigen::Matrix<double, 7, 6, Eigen::RowMajor> plus_jacobian;
  const PoseManifold manifold;
  manifold.PlusJacobian(x, plus_jacobian.data());
  Eigen::Matrix<double, kMaxRows, 7, Eigen::RowMajor> J_ambient;
  double* jacobians[1] = {J_ambient.data()};
  Eigen::Matrix<double, kMaxRows, 1> r;
  double total = 0.0;
  for (const auto& f : residuals) {
    const int rows = f->num_residuals();
    if (rows > kMaxRows) return false;
    if (!f->Evaluate(parameters, r.data(), lin ? jacobians : nullptr)) return false;
    const double s = r.head(rows).squaredNorm();
    double w = 1.0;
    total += Rho(loss, s, lin ? &w : nullptr);
    if (!lin) continue;
    // Tangent Jacobian (fixed-capacity storage: no allocation per residual).
    const Eigen::Matrix<double, Eigen::Dynamic, 6, 0, kMaxRows, 6> J =
        J_ambient.topRows(rows) * plus_jacobian;
    lin->H.noalias() += w * J.transpose() * J;
    lin->g.noalias() += w * J.transpose() * r.head(rows);
  }
  *cost = 0.5 * total;
  if (lin) lin->cost = *cost;
  return std::isfinite(total) && (!lin || (lin->H.allFinite() && lin->g.allFinite()));
}

}  // namespace

PoseSolverSummary SolvePose(const std::vector<std::unique_ptr<ceres::CostFunction>>& residuals,
                            const ceres::LossFunction* loss, const PoseSolverOptions& options,
                            SE3d* T_w_s) {
  PoseSolverSummary summary;
  if (residuals.empty()) {
    summary.message = "no residuals";
    return summary;
  }
  Linearisation lin;
  double cost = 0.0;
  if (!Evaluate(residuals, loss, *T_w_s, &cost, &lin)) {
    summary.message = "a residual failed to evaluate at the initial pose";
    return summary;
  }
  summary.initial_cost = summary.final_cost = cost;
  summary.usable = true;
  double lambda = options.initial_lambda;
  for (int it = 0; it < options.max_iterations; ++it) {
    ++summary.iterations;
    Matrix6d A = lin.H;
    A.diagonal() += lambda * lin.H.diagonal().cwiseMax(1e-12);
    const Eigen::LDLT<Matrix6d> ldlt(A);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) {
      summary.usable = it > 0;
      summary.message = "singular normal equations";
      break;
    }
    const Vector6d dx = ldlt.solve(-lin.g);
    if (!dx.allFinite()) {
      summary.message = "non-finite step";
      break;
    }
    const SE3d T_new = T_w_s->Plus(dx);
    double new_cost = 0.0;
    if (Evaluate(residuals, loss, T_new, &new_cost, nullptr) && new_cost < cost) {
      const double decrease = (cost - new_cost) / std::max(cost, 1e-300);
      *T_w_s = T_new;
      cost = new_cost;
      lambda = std::max(lambda / 10.0, 1e-12);
      if (decrease < options.function_tolerance || dx.norm() < options.step_tolerance) break;
      if (it + 1 < options.max_iterations && !Evaluate(residuals, loss, *T_w_s, &cost, &lin)) {
        summary.message = "a residual failed to evaluate";
        break;
      }
    } else {
      lambda *= 10.0;
      if (dx.norm() < options.step_tolerance) break;
    }
  }
  summary.final_cost = cost;
  return summary;
}

}  // namespace lidar
}  // namespace plucker
