#include "plucker/lidar/pose_solver.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "plucker/factors/pose_manifold.h"

namespace plucker {
namespace lidar {
namespace {

constexpr int kMaxRows = 3;  // largest residual block of the LiDAR factors

using AmbientJacobian = Eigen::Matrix<double, kMaxRows, 7, Eigen::RowMajor>;
using PlusJacobian = Eigen::Matrix<double, 7, 6, Eigen::RowMajor>;

// H += w J^T J and g += w J^T r for one residual block of kRows rows, J = J_ambient P (tangent).
template <int kRows>
void AddBlock(const AmbientJacobian& J_ambient, const PlusJacobian& P, const double* r, double w,
              NormalEquations* eq) {
  const Eigen::Matrix<double, kRows, 6> J = J_ambient.topRows<kRows>() * P;
  eq->H.noalias() += (w * J.transpose()) * J;
  eq->g.noalias() += (w * J.transpose()) * Eigen::Matrix<double, kRows, 1>::Map(r);
}

}  // namespace

bool EvaluateNormalEquations(const std::vector<std::unique_ptr<ceres::CostFunction>>& residuals,
                             const ceres::LossFunction* loss, const SE3d& T_w_s,
                             NormalEquations* eq) {
  *eq = NormalEquations();
  double x[7];
  T_w_s.ToParameters(x);
  const double* parameters[1] = {x};
  PlusJacobian plus_jacobian;
  const PoseManifold manifold;
  manifold.PlusJacobian(x, plus_jacobian.data());
  AmbientJacobian J_ambient;
  double* jacobians[1] = {J_ambient.data()};
  double r[kMaxRows];
  double total = 0.0;
  for (const auto& f : residuals) {
    const int rows = f->num_residuals();
    if (rows > kMaxRows || !f->Evaluate(parameters, r, jacobians)) return false;
    double rho[3] = {Eigen::VectorXd::Map(r, rows).squaredNorm(), 1.0, 0.0};  // rho(s) = s
    if (loss != nullptr) loss->Evaluate(rho[0], rho);
    total += rho[0];
    const double w = rho[1];
    if (rows == 1) AddBlock<1>(J_ambient, plus_jacobian, r, w, eq);
    if (rows == 2) AddBlock<2>(J_ambient, plus_jacobian, r, w, eq);
    if (rows == 3) AddBlock<3>(J_ambient, plus_jacobian, r, w, eq);
    eq->num_residuals += rows;
  }
  eq->cost = 0.5 * total;
  return std::isfinite(total) && eq->H.allFinite() && eq->g.allFinite();
}

PoseSolverSummary SolvePose(const std::vector<std::unique_ptr<ceres::CostFunction>>& residuals,
                            const ceres::LossFunction* loss, const PoseSolverOptions& options,
                            SE3d* T_w_s) {
  PoseSolverSummary summary;
  if (residuals.empty()) {
    summary.message = "no residuals";
    return summary;
  }
  NormalEquations& eq = summary.normal_equations;  // always at *T_w_s
  if (!EvaluateNormalEquations(residuals, loss, *T_w_s, &eq)) {
    summary.message = "a residual failed to evaluate at the initial pose";
    return summary;
  }
  summary.initial_cost = eq.cost;
  summary.usable = true;
  double lambda = options.initial_lambda;
  NormalEquations trial;
  for (int it = 0; it < options.max_iterations; ++it) {
    ++summary.iterations;
    Matrix6d A = eq.H;
    A.diagonal() += lambda * eq.H.diagonal().cwiseMax(1e-12);
    const Eigen::LDLT<Matrix6d> ldlt(A);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) {
      summary.usable = it > 0;
      summary.message = "singular normal equations";
      break;
    }
    const Vector6d dx = ldlt.solve(-eq.g);
    if (!dx.allFinite()) {
      summary.message = "non-finite step";
      break;
    }
    const SE3d T_new = T_w_s->Plus(dx);
    if (EvaluateNormalEquations(residuals, loss, T_new, &trial) && trial.cost < eq.cost) {
      const double decrease = (eq.cost - trial.cost) / std::max(eq.cost, 1e-300);
      *T_w_s = T_new;
      std::swap(eq, trial);
      lambda = std::max(lambda / 10.0, 1e-12);
      if (decrease < options.function_tolerance || dx.norm() < options.step_tolerance) break;
    } else {
      lambda *= 10.0;
      if (dx.norm() < options.step_tolerance) break;
    }
  }
  summary.final_cost = eq.cost;
  return summary;
}

}  // namespace lidar
}  // namespace plucker
