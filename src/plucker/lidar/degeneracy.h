// Degeneracy of scan-to-map registration (after Zhang, Kaess and Singh, ICRA 2016) with a
// unit-free criterion; docs/math/lidar-odometry.md ("Normal equations and degeneracy") derives it
// and has the measurements behind every threshold. From the solution's normal equations over N
// rows, H_n = H / N (tangent (dtheta, dt)), rotation and translation are analysed apart, each
// after marginalising the other (Schur complements, eigenvalues mu0 <= mu1 <= mu2); a direction
// is flagged when its eigen-gap ratio (1, mu1 / mu2, min(mu0 / mu1, mu1 / mu2)) is below the
// block's threshold AND its information below the block's ceiling. Remapping keeps the prior
// along the flagged directions C: delta' = delta - H^-1 C (C^T H^-1 C)^-1 C^T delta.
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
  // Of H_n (diagnostics only), ascending.
  Vector6d eigenvalues = Vector6d::Zero();
  Matrix6d eigenvectors = Matrix6d::Identity();  // columns, same order
  // Per block: Schur complement eigenvalues (ascending, per row), eigenvectors (columns) and
  // the criterion's ratio of each (1 for the strongest, 0 when the block is empty).
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
