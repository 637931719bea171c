#include "plucker/lidar/degeneracy.h"

#include <Eigen/Eigenvalues>

namespace plucker {
namespace lidar {

void NormalEquations::AddPlane(const SE3d& T_w_s, const Eigen::Vector3d& p_s,
                               const Eigen::Vector3d& m_w, double sigma) {
  // d p_w / d dtheta = -R [p_s]x, d p_w / d dt = I.
  Eigen::Matrix<double, 1, 6> J;
  J.head<3>() = -(m_w.transpose() * T_w_s.RotationMatrix() * Hat<double>(p_s));
  J.tail<3>() = m_w.transpose();
  J /= sigma;
  H_.noalias() += J.transpose() * J;
  rows_ += 1;
}

void NormalEquations::AddEdge(const SE3d& T_w_s, const Eigen::Vector3d& p_s,
                              const Eigen::Vector3d& u_w, double sigma) {
  const Eigen::Matrix3d U = Hat<double>(u_w);
  Eigen::Matrix<double, 3, 6> J;
  J.leftCols<3>() = -U * T_w_s.RotationMatrix() * Hat<double>(p_s);
  J.rightCols<3>() = U;
  J /= sigma;
  H_.noalias() += J.transpose() * J;
  rows_ += 2;  // rank 2: the component along u is identically zero
}

DegeneracyInfo NormalEquations::Analyse(double threshold) const {
  DegeneracyInfo info;
  if (rows_ == 0) {
    info.degenerate = true;
    info.num_degenerate_directions = 6;
    return info;
  }
  Eigen::SelfAdjointEigenSolver<Matrix6d> solver(H_ / rows_);
  info.eigenvalues = solver.eigenvalues();
  info.eigenvectors = solver.eigenvectors();
  for (int i = 0; i < 6; ++i)
    if (info.eigenvalues(i) < threshold) ++info.num_degenerate_directions;
  info.degenerate = info.num_degenerate_directions > 0;
  return info;
}

SE3d RemapSolution(const SE3d& T_prior, const SE3d& T_solution, const DegeneracyInfo& info,
                   double threshold) {
  if (!info.degenerate) return T_solution;
  Matrix6d P = Matrix6d::Zero();
  for (int i = 0; i < 6; ++i) {
    if (info.eigenvalues(i) < threshold) continue;
    const Vector6d v = info.eigenvectors.col(i);
    P += v * v.transpose();
  }
  return T_prior.Plus(P * T_solution.Minus(T_prior));
}

}  // namespace lidar
}  // namespace plucker
