#include "plucker/geometry/fitting.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

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

namespace {

// The largest (side = 1) or the smallest (side = -1) root of mu^3 - p mu - q, whose three roots are
// real, sum to 0 and lie within 2 sqrt(p / 3) of it, and (for a positive semi-definite matrix)
// within `bound`.
// Newton's method from the nearer bound: beyond the root the cubic is monotone and convex
// (concave), so the iterates approach the root from outside; they stop when a step is below
// rounding or turns back (a double root converges only linearly: <= 100 steps).
double ExtremeCubicRoot(double p, double q, double side, double bound) {
  const double outer = 2.0 * std::sqrt(p / 3.0);
  double mu = side * std::min(outer, side * bound);
  // Beyond the root, mu has the sign of `side`, the cubic too, and its slope is positive (mu is
  // past the critical point sqrt(p / 3) on that side). If not, `bound` did not hold (a matrix that
  // is not positive semi-definite): start from the bound that always holds.
  const bool beyond =
      side * mu >= 0.0 && 3.0 * mu * mu - p >= 0.0 && side * ((mu * mu - p) * mu - q) >= 0.0;
  if (!beyond) mu = side * outer;
  for (int it = 0; it < 100; ++it) {
    const double step = ((mu * mu - p) * mu - q) / (3.0 * mu * mu - p);
    if (!(side * step > 0.0)) break;
    mu -= step;
    if (side * step < 1e-10) break;  // the error left is ~ step^2 / gap: below rounding
  }
  return mu;
}

ExtremeEigenpair FullSolverEigenpair(const Eigen::Matrix3d& A, double side) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(A);  // ascending
  const int end = side > 0 ? 2 : 0;
  ExtremeEigenpair eig;
  eig.value = es.eigenvalues()(end);
  eig.middle = es.eigenvalues()(1);
  eig.vector = es.eigenvectors().col(end);
  eig.fallback = true;
  return eig;
}

ExtremeEigenpair ExtremeEigenpairOf(const Eigen::Matrix3d& A, double side) {
  Eigen::Matrix3d C = A.selfadjointView<Eigen::Lower>();
  const double shift = C.trace() / 3.0;
  C.diagonal().array() -= shift;
  const double scale = C.cwiseAbs().maxCoeff();
  if (!(scale > 0.0) || !std::isfinite(scale)) return FullSolverEigenpair(A, side);
  C *= 1.0 / scale;  // eigenvalues within [-2, 2], summing to 0
  const double p =
      0.5 * C.diagonal().squaredNorm() + C(1, 0) * C(1, 0) + C(2, 0) * C(2, 0) + C(2, 1) * C(2, 1);
  // Positive semi-definite: every eigenvalue is within [0, trace], i.e. mu within
  // [-shift, 2 shift] / scale (for a plane's smallest or an edge's largest, nearly at that bound).
  const double mu =
      ExtremeCubicRoot(p, C.determinant(), side, (side > 0 ? 2.0 : -1.0) * shift / scale);
  // The other two roots: a + b = -mu, a b = mu^2 - p; the middle one is on the side of mu.
  const double middle = 0.5 * (-mu + side * std::sqrt(std::max(0.0, 4.0 * p - 3.0 * mu * mu)));
  // The rows' cross products are the rows of adj(C - mu I) = (mu_a - mu)(mu_b - mu) v v^T.
  C.diagonal().array() -= mu;
  const Eigen::Vector3d c[3] = {C.row(0).cross(C.row(1)), C.row(0).cross(C.row(2)),
                                C.row(1).cross(C.row(2))};
  const double n[3] = {c[0].squaredNorm(), c[1].squaredNorm(), c[2].squaredNorm()};
  const int best = n[0] >= n[1] ? (n[0] >= n[2] ? 0 : 2) : (n[1] >= n[2] ? 1 : 2);
  // |gap product| >= 1e-4: the longest row of adj is >= its 1/sqrt(3), squared 3.3e-9.
  if (!(n[best] > 3.3e-9)) return FullSolverEigenpair(A, side);
  ExtremeEigenpair eig;
  eig.value = shift + scale * mu;
  eig.middle = shift + scale * middle;
  eig.vector = c[best] / std::sqrt(n[best]);
  return eig;
}

}  // namespace

ExtremeEigenpair SmallestEigenpair(const Eigen::Matrix3d& A) { return ExtremeEigenpairOf(A, -1.0); }
ExtremeEigenpair LargestEigenpair(const Eigen::Matrix3d& A) { return ExtremeEigenpairOf(A, 1.0); }

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
