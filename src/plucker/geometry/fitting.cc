#include "plucker/geometry/fitting.h"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace plucker {

const char* ToString(FitStatus status) {
  switch (status) {
    case FitStatus::kOk:
      return "ok";
    case FitStatus::kTooFewPoints:
      return "too few points";
    case FitStatus::kNonFinite:
      return "non-finite point";
    case FitStatus::kDegenerate:
      return "degenerate (coincident or collinear points)";
  }
  return "unknown";
}

std::optional<Eigen::Vector4d> NormalizePlane(const Eigen::Vector4d& plane) {
  const double norm = plane.head<3>().norm();
  if (!plane.allFinite() || !(norm > 0)) return std::nullopt;
  return Eigen::Vector4d(plane / norm);
}

PlaneFit PlaneFromPoints(const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                         const Eigen::Vector3d& p3, const FitOptions& options) {
  PlaneFit fit;
  fit.num_points = 3;
  if (!p1.allFinite() || !p2.allFinite() || !p3.allFinite()) {
    fit.status = FitStatus::kNonFinite;
    return fit;
  }
  const Eigen::Vector3d a = p2 - p1, b = p3 - p1;
  const Eigen::Vector3d m = a.cross(b);
  const double la = a.norm(), lb = b.norm(), lm = m.norm();
  fit.status = FitStatus::kDegenerate;
  if (!(std::min(la, lb) > options.min_extent)) return fit;
  if (!(lm > options.min_relative_spread * la * lb)) return fit;  // sin(angle at p1)
  fit.status = FitStatus::kOk;
  fit.centroid = (p1 + p2 + p3) / 3.0;
  fit.plane.head<3>() = m / lm;
  fit.plane(3) = -fit.plane.head<3>().dot(fit.centroid);
  return fit;
}

namespace fitting_internal {

namespace {
// Eigen-decomposition of the covariance (ascending eigenvalues, clamped at 0) or false when the
// points are coincident.
bool Decompose(const Eigen::Matrix3d& cov, const FitOptions& options, Eigen::Vector3d* values,
               Eigen::Matrix3d* vectors) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(cov);
  if (es.info() != Eigen::Success) return false;
  *values = es.eigenvalues().cwiseMax(0.0);
  *vectors = es.eigenvectors();
  return std::sqrt((*values)(2)) > options.min_extent;
}
}  // namespace

PlaneFit PlaneFromMoments(int n, const Eigen::Vector3d& centroid, const Eigen::Matrix3d& cov,
                          const FitOptions& options) {
  PlaneFit fit;
  fit.num_points = n;
  if (n < 3) return fit;  // kTooFewPoints
  fit.centroid = centroid;
  Eigen::Vector3d values;
  Eigen::Matrix3d vectors;
  fit.status = FitStatus::kDegenerate;
  if (!Decompose(cov, options, &values, &vectors)) return fit;
  if (!(std::sqrt(values(1)) > options.min_relative_spread * std::sqrt(values(2)))) return fit;
  fit.status = FitStatus::kOk;
  fit.eigenvalues = values;
  const Eigen::Vector3d m = vectors.col(0).normalized();
  fit.plane << m, -m.dot(centroid);
  return fit;
}

LineFit LineFromMoments(int n, const Eigen::Vector3d& centroid, const Eigen::Matrix3d& cov,
                        const FitOptions& options) {
  LineFit fit;
  fit.num_points = n;
  if (n < 2) return fit;  // kTooFewPoints
  fit.centroid = centroid;
  Eigen::Vector3d values;
  Eigen::Matrix3d vectors;
  fit.status = FitStatus::kDegenerate;
  if (!Decompose(cov, options, &values, &vectors)) return fit;
  fit.status = FitStatus::kOk;
  fit.eigenvalues = values;
  const Eigen::Vector3d d = vectors.col(2).normalized();
  fit.L << centroid.cross(d), d;
  fit.linearity_ratio = values(1) / values(2);
  return fit;
}

}  // namespace fitting_internal

}  // namespace plucker
