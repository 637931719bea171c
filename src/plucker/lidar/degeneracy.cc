#include "plucker/lidar/degeneracy.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>

namespace plucker {
namespace lidar {
namespace {

// Pseudo-inverse of a symmetric PSD 3x3 matrix (eigenvalues < 1e-12 of the largest: zero).
Eigen::Matrix3d PseudoInverse(const Eigen::Matrix3d& A) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(A);
  const Eigen::Vector3d mu = solver.eigenvalues();
  const double cutoff = 1e-12 * std::max(mu(2), 0.0);
  Eigen::Vector3d inv = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i)
    if (mu(i) > cutoff && mu(i) > 0.0) inv(i) = 1.0 / mu(i);
  return solver.eigenvectors() * inv.asDiagonal() * solver.eigenvectors().transpose();
}

// a / b for the criterion: 0 when b is not positive (no information at all).
double Ratio(double a, double b) { return b > 0.0 ? std::max(a, 0.0) / b : 0.0; }

// Eigen-decomposition of a Schur complement and the eigen-gap ratios of its directions.
void AnalyseBlock(const Eigen::Matrix3d& S, Eigen::Vector3d* information,
                  Eigen::Matrix3d* directions, Eigen::Vector3d* ratios) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(0.5 * (S + S.transpose()));
  *information = solver.eigenvalues();
  *directions = solver.eigenvectors();
  const Eigen::Vector3d& mu = *information;
  (*ratios)(2) = mu(2) > 0.0 ? 1.0 : 0.0;
  (*ratios)(1) = Ratio(mu(1), mu(2));
  (*ratios)(0) = std::min(Ratio(mu(0), mu(1)), (*ratios)(1));
}

Eigen::Vector3i Flags(const Eigen::Vector3d& ratios, const Eigen::Vector3d& information,
                      double max_ratio, double max_information) {
  Eigen::Vector3i flags;
  for (int i = 0; i < 3; ++i)
    flags(i) = ratios(i) < max_ratio && !(information(i) >= max_information) ? 1 : 0;
  return flags;
}

}  // namespace

DegeneracyInfo AnalyseDegeneracy(const Matrix6d& H, int rows,
                                 const DegeneracyCriterion& criterion) {
  DegeneracyInfo info;
  if (rows <= 0 || !H.allFinite()) {
    info.degenerate = true;
    info.num_degenerate_rotations = info.num_degenerate_translations = 3;
    info.num_degenerate_directions = 6;
    info.rotation_flags.setOnes();
    info.translation_flags.setOnes();
    return info;
  }
  const Matrix6d Hn = H / rows;
  info.information = Hn;
  Eigen::SelfAdjointEigenSolver<Matrix6d> solver(Hn);
  info.eigenvalues = solver.eigenvalues();
  info.eigenvectors = solver.eigenvectors();

  const Eigen::Matrix3d H_rr = Hn.topLeftCorner<3, 3>();
  const Eigen::Matrix3d H_tt = Hn.bottomRightCorner<3, 3>();
  const Eigen::Matrix3d H_rt = Hn.topRightCorner<3, 3>();
  const Eigen::Matrix3d S_r = H_rr - H_rt * PseudoInverse(H_tt) * H_rt.transpose();
  const Eigen::Matrix3d S_t = H_tt - H_rt.transpose() * PseudoInverse(H_rr) * H_rt;
  AnalyseBlock(S_r, &info.rotation_information, &info.rotation_directions, &info.rotation_ratios);
  AnalyseBlock(S_t, &info.translation_information, &info.translation_directions,
               &info.translation_ratios);
  info.rotation_flags = Flags(info.rotation_ratios, info.rotation_information,
                              criterion.rotation_ratio, criterion.max_rotation_information);
  info.translation_flags =
      Flags(info.translation_ratios, info.translation_information, criterion.translation_ratio,
            criterion.max_translation_information);
  info.num_degenerate_rotations = info.rotation_flags.sum();
  info.num_degenerate_translations = info.translation_flags.sum();
  info.num_degenerate_directions = info.num_degenerate_rotations + info.num_degenerate_translations;
  info.degenerate = info.num_degenerate_directions > 0;
  return info;
}

SE3d RemapSolution(const SE3d& T_prior, const SE3d& T_solution, const DegeneracyInfo& info) {
  if (!info.degenerate) return T_solution;
  // The flagged directions as constraints C^T delta = 0.
  Eigen::Matrix<double, 6, Eigen::Dynamic> C = Eigen::Matrix<double, 6, 6>::Zero();
  int k = 0;
  for (int i = 0; i < 6; ++i) {  // rotations (dtheta) first, then translations (dt)
    const bool rotation = i < 3;
    if (!(rotation ? info.rotation_flags : info.translation_flags)(i % 3)) continue;
    C.col(k++).segment<3>(rotation ? 0 : 3) =
        (rotation ? info.rotation_directions : info.translation_directions).col(i % 3);
  }
  if (k == 0) return T_solution;
  if (k == 6) return T_prior;
  C.conservativeResize(6, k);
  const Vector6d delta = T_solution.Minus(T_prior);
  // H^-1 C, regularised per block (H may be singular; C^T delta' = 0 holds exactly anyway).
  Matrix6d H = info.information;
  const double scale_r = std::max(H.topLeftCorner<3, 3>().trace() / 3.0, 1e-300);
  const double scale_t = std::max(H.bottomRightCorner<3, 3>().trace() / 3.0, 1e-300);
  H.diagonal().head<3>().array() += 1e-9 * scale_r;
  H.diagonal().tail<3>().array() += 1e-9 * scale_t;
  const Eigen::Matrix<double, 6, Eigen::Dynamic> W = H.ldlt().solve(C);
  const Eigen::MatrixXd M = C.transpose() * W;
  Vector6d remapped = delta - W * M.ldlt().solve(C.transpose() * delta);
  // Fallback (non-finite H): orthogonal projection (the columns of C are orthonormal).
  if (!remapped.allFinite()) remapped = delta - C * (C.transpose() * delta);
  return T_prior.Plus(remapped);
}

}  // namespace lidar
}  // namespace plucker
