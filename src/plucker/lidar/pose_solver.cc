#include "plucker/lidar/pose_solver.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace plucker {
namespace lidar {
namespace {

using Vector1d = Eigen::Matrix<double, 1, 1>;

// One residual r (tangent Jacobian J): H += w J^T J, g += w J^T r, *total += rho(|r|^2).
template <int kRows>
void AddResidual(const Eigen::Matrix<double, kRows, 6>& J, const Eigen::Matrix<double, kRows, 1>& r,
                 const ceres::LossFunction* loss, double* total, NormalEquations* eq) {
  double rho[3] = {r.squaredNorm(), 1.0, 0.0};  // rho(s) = s
  if (loss != nullptr) loss->Evaluate(rho[0], rho);
  *total += rho[0];
  eq->H.noalias() += (rho[1] * J.transpose()) * J;
  eq->g.noalias() += (rho[1] * J.transpose()) * r;
  eq->num_residuals += kRows;
}

}  // namespace

bool EvaluateNormalEquations(const LidarResiduals& residuals, const ceres::LossFunction* loss,
                             const SE3d& T_w_s, NormalEquations* eq) {
  *eq = NormalEquations();
  const Eigen::Matrix3d R_w_s = T_w_s.RotationMatrix();
  const Eigen::Vector3d& t_w_s = T_w_s.translation();
  double total = 0.0;
  Eigen::Matrix<double, 1, 6> J_plane;
  Eigen::Matrix<double, 3, 6> J_edge;
  for (const PlaneResidual& f : residuals.planes)
    AddResidual<1>(J_plane, Vector1d(f.Evaluate(R_w_s, t_w_s, &J_plane)), loss, &total, eq);
  for (const EdgeResidual& f : residuals.edges)
    AddResidual<3>(J_edge, f.Evaluate(R_w_s, t_w_s, &J_edge), loss, &total, eq);
  eq->cost = 0.5 * total;
  return std::isfinite(total) && eq->H.allFinite() && eq->g.allFinite();
}

PoseSolverSummary SolvePose(const LidarResiduals& residuals, const ceres::LossFunction* loss,
                            const PoseSolverOptions& options, SE3d* T_w_s) {
  PoseSolverSummary summary;
  if (residuals.empty()) {
    summary.message = "no residuals";
    return summary;
  }
  NormalEquations& eq = summary.normal_equations;  // always at *T_w_s
  if (!EvaluateNormalEquations(residuals, loss, *T_w_s, &eq)) {
    summary.message = "non-finite normal equations at the initial pose";
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
