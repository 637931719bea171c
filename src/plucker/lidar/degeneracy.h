// Degeneracy of scan-to-map registration (after Zhang, Kaess and Singh, "On degeneracy of
// optimization-based state estimation problems", ICRA 2016), with a noise-robust, unit-free
// criterion. docs/math/lidar-odometry.md, "Normal equations and degeneracy", derives it and has
// the measurements behind every threshold.
//
// Input: the normal equations H = sum_i w_i J_i^T J_i of the solution (SolvePose returns them;
// tangent (dtheta, dt), residuals in units of their sigma), normalised by the number of residual
// rows N: H_n = H / N. Rotation and translation are analysed apart, each after marginalising the
// other: S_t = H_tt - H_rt^T H_rr^-1 H_rt, S_r = H_rr - H_rt H_tt^-1 H_rt^T, eigenvalues
// mu0 <= mu1 <= mu2. A direction is flagged when its eigen-gap to the next stronger direction,
//   ratio(mu2) = 1,  ratio(mu1) = mu1 / mu2,  ratio(mu0) = min(mu0 / mu1, mu1 / mu2),
// is below the block's threshold AND its information is below the block's ceiling (which keeps
// an open square with a dominant ground plane unflagged). The ratios do not change with a global
// scaling of H (sigma, N, the number of points).
//
// Solution remapping: along the flagged directions C (6 x k) the prior (the constant-velocity
// prediction) is kept, and the other coordinates take the value the quadratic model H gives under
// that constraint: with delta = T_solution - T_prior,
//   delta' = delta - H^-1 C (C^T H^-1 C)^-1 C^T delta,   so C^T delta' = 0
// (for a direction decoupled from the others, the orthogonal projection of Zhang et al.).
#pragma once

#include <Eigen/Core>
#include <limits>

#include "plucker/geometry/se3.h"

namespace plucker {
namespace lidar {

struct DegeneracyInfo {
  bool degenerate = false;
  int num_degenerate_directions = 0;  // rotation + translation directions flagged
  int num_degenerate_rotations = 0, num_degenerate_translations = 0;
  // Of H_n (reported for diagnostics; the criterion uses the blocks below), ascending.
  Vector6d eigenvalues = Vector6d::Zero();
  Matrix6d eigenvectors = Matrix6d::Identity();  // columns, same order
  // Per block: eigenvalues of the Schur complement (ascending; m^2 / sigma^2 for rotation,
  // 1 / sigma^2 for translation, per row), its eigenvectors (columns, same order) and the
  // criterion's ratio of each (1 for the strongest, 0 when the block is empty).
  Eigen::Vector3d rotation_information = Eigen::Vector3d::Zero();
  Eigen::Vector3d translation_information = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation_directions = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d translation_directions = Eigen::Matrix3d::Identity();
  Eigen::Vector3d rotation_ratios = Eigen::Vector3d::Zero();
  Eigen::Vector3d translation_ratios = Eigen::Vector3d::Zero();
  Matrix6d information = Matrix6d::Zero();  // H_n
  // Which block directions (columns of *_directions) are flagged.
  Eigen::Vector3i rotation_flags = Eigen::Vector3i::Zero();
  Eigen::Vector3i translation_flags = Eigen::Vector3i::Zero();
};

// Per block: the eigen-gap ratio threshold and the ceiling on the information (per row) of a
// flagged direction.
struct DegeneracyCriterion {
  double translation_ratio = 0.03;
  double rotation_ratio = 0.01;
  double max_translation_information = std::numeric_limits<double>::infinity();  // 1/sigma^2
  double max_rotation_information = std::numeric_limits<double>::infinity();     // m^2/sigma^2
};

// Analyses H over `rows` independent residual rows (a plane row 1, a point-to-edge block 2). No
// rows, or a non-finite H: every direction is flagged.
DegeneracyInfo AnalyseDegeneracy(const Matrix6d& H, int rows, const DegeneracyCriterion& criterion);

// Solution remapping (see above) along the flagged directions; T_solution when none is.
SE3d RemapSolution(const SE3d& T_prior, const SE3d& T_solution, const DegeneracyInfo& info);

}  // namespace lidar
}  // namespace plucker
