// Degeneracy of scan-to-map registration (after Zhang, Kaess and Singh, "On degeneracy of
// optimization-based state estimation problems", ICRA 2016), with a noise-robust, unit-free
// criterion (docs/math/lidar-odometry.md, "Normal equations and degeneracy", has the
// measurements behind it).
//
// The normal equations of the linearised problem at the solution, H = sum_i w_i J_i^T J_i (6x6,
// tangent (dtheta, dt) of the pose manifold, residuals in units of their sigma, w_i the robust
// weights; SolvePose returns them), are normalised by the number of residual rows N: H_n = H / N.
//
// Criterion. Rotation (m^2) and translation (1) have different units, so each is analysed on its
// own, after marginalising the other (a translation that a rotation can compensate is not
// constrained): the Schur complements
//   S_t = H_tt - H_rt^T H_rr^-1 H_rt,   S_r = H_rr - H_rt H_tt^-1 H_rt^T,
// with eigenvalues mu0 <= mu1 <= mu2. A direction is degenerate when its information is a small
// fraction of the NEXT stronger direction of the same block (an eigen-gap):
//   ratio(mu1) = mu1 / mu2,   ratio(mu0) = min(mu0 / mu1, mu1 / mu2),   ratio(mu2) = 1,
// flagged when ratio < threshold for translations and < RotationThreshold(threshold) =
// threshold / 3 for rotations (AnalyseDegeneracy with a threshold); with a DegeneracyCriterion it
// sets both ratios and also requires the direction's information to be below a ceiling per block
// (the odometry uses 1.3 for translations and leaves rotations unflagged: LidarOdometryOptions).
// The ratios are invariant to a global scaling of H (sigma, N, the number of points). With noisy
// range the fitted plane normals tilt, which adds about (tilt / sigma)^2 of information per row
// along a corridor axis: that made the old absolute test (eigenvalue of H_n < 0.3) miss corridors
// at 2 cm noise, but it stays a small fraction of the next direction (0.2-2% in the simulated
// corridors at 0.5-3 cm), whereas real along-track constraints are >= 4% in the simulated streets
// and >= 36% on KITTI even when the ground plane dominates. Rotation information carries the
// squared lever arm of the points (1-100 m), so well-constrained rotations show smaller gaps
// (>= 2.4% measured: yaw in a street, roll in a corridor) while a free rotation's noise floor is ~2
// tilt^2 (< 0.5%); hence threshold / 3.
//
// Solution remapping: along the flagged directions the prior (the constant-velocity prediction)
// is kept and the other coordinates take the value that the quadratic model H of the solution
// gives under that constraint: with C the flagged directions (6 x k, [v; 0] for a rotation,
// [0; v] for a translation) and delta = T_solution - T_prior,
//   delta' = delta - H^-1 C (C^T H^-1 C)^-1 C^T delta,   so C^T delta' = 0.
// (For a direction decoupled from the others this is the orthogonal projection of Zhang et al.)
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
  // criterion's ratio of each (see above; 1 for the strongest, 0 when the block is empty).
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

// A direction of a block is flagged when its eigen-gap ratio is below the block's ratio AND its
// information (Schur-complement eigenvalue of H_n) is below the block's absolute ceiling. The
// ceiling keeps a scene whose ground plane dominates (an open square with facades far away) from
// being flagged although every direction is well determined in absolute terms.
struct DegeneracyCriterion {
  double translation_ratio = 0.03;
  double rotation_ratio = 0.01;
  double max_translation_information = std::numeric_limits<double>::infinity();  // 1/sigma^2
  double max_rotation_information = std::numeric_limits<double>::infinity();     // m^2/sigma^2
};

// Analyses the normal equations H = J^T W J of the solution (pose_solver.h: NormalEquations,
// tangent (dtheta, dt), residuals in units of their sigma) over `rows` independent residual rows
// (a plane row 1, a point-to-edge block 2: its 3 residuals have rank 2). The threshold form
// flags the directions whose eigen-gap ratio is below `threshold` (translations) or
// RotationThreshold(threshold) (rotations); unit-free, default 0.03. No rows, or a non-finite
// H: every direction is flagged.
DegeneracyInfo AnalyseDegeneracy(const Matrix6d& H, int rows, double threshold);
DegeneracyInfo AnalyseDegeneracy(const Matrix6d& H, int rows, const DegeneracyCriterion& criterion);

// The threshold applied to rotation ratios: threshold / 3 (see above).
double RotationThreshold(double threshold);

// Solution remapping (see above) along the directions flagged in `info`. Returns T_solution
// when none is.
SE3d RemapSolution(const SE3d& T_prior, const SE3d& T_solution, const DegeneracyInfo& info);

}  // namespace lidar
}  // namespace plucker
