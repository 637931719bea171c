// Degeneracy of scan-to-map registration (after Zhang, Kaess and Singh, "On degeneracy of
// optimization-based state estimation problems", ICRA 2016).
//
// The normal equations of the linearised problem at the solution, H = sum_i J_i^T J_i (6x6,
// tangent (dtheta, dt) of the pose manifold, residuals in units of their sigma), are normalised by
// the number of residual rows N: H_n = H / N, the average information per residual row (units:
// m^2 for rotation, 1 for translation). A direction v (eigenvector of H_n) with eigenvalue below
// `threshold` is poorly constrained (e.g. along a corridor whose walls, floor and ceiling are all
// parallel to its axis). The estimate is then kept stable by solution remapping: the update from
// the prior pose (the constant-velocity prediction) is projected onto the well-constrained
// eigenvectors, so along degenerate directions the prior is kept.
#pragma once

#include <Eigen/Core>

#include "plucker/geometry/se3.h"

namespace plucker {
namespace lidar {

struct DegeneracyInfo {
  bool degenerate = false;
  int num_degenerate_directions = 0;
  Vector6d eigenvalues = Vector6d::Zero();       // of H_n, ascending
  Matrix6d eigenvectors = Matrix6d::Identity();  // columns, same order
};

// Accumulates J^T J of residual rows (tangent Jacobians) and analyses it.
class NormalEquations {
 public:
  // A point-to-plane row: r = m . (R p_s + t - q) / sigma.
  void AddPlane(const SE3d& T_w_s, const Eigen::Vector3d& p_s, const Eigen::Vector3d& m_w,
                double sigma);
  // A point-to-line block: r = u x (R p_s + t - a) / sigma (3 rows, rank 2).
  void AddEdge(const SE3d& T_w_s, const Eigen::Vector3d& p_s, const Eigen::Vector3d& u_w,
               double sigma);
  const Matrix6d& H() const { return H_; }
  int rows() const { return rows_; }
  DegeneracyInfo Analyse(double threshold) const;

 private:
  Matrix6d H_ = Matrix6d::Zero();
  int rows_ = 0;
};

// Solution remapping: T_prior.Plus(P (T_solution.Minus(T_prior))), P projecting onto the
// eigenvectors whose eigenvalue is >= threshold. Returns T_solution when not degenerate.
SE3d RemapSolution(const SE3d& T_prior, const SE3d& T_solution, const DegeneracyInfo& info,
                   double threshold);

}  // namespace lidar
}  // namespace plucker
