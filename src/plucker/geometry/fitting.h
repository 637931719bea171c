// Planes and lines fitted to 3D points (used by the LiDAR odometry to validate edge and plane
// correspondences, so everything here is allocation-free: the fits take iterators over Eigen
// 3-vectors (double or float), accumulate the 3x3 covariance about the centroid by hand (two
// passes, so coordinates far from the origin lose no precision) and use Eigen's closed-form 3x3
// eigensolver (computeDirect: ~2x faster than the iterative one; the eigenvector used is always
// the well-separated one of an accepted fit). Distance statistics are computed from the points.
// Measured: ~0.8 us per 5-point plane fit on the shared build machine, no heap allocation.
// Derivations: docs/math/projection-triangulation.md.
//
// Planes are pi = (m, e) with |m| = 1 and m . x + e = 0 (docs/conventions.md); lines are Plücker
// [n; d] with |d| = 1 and n = c x d for the centroid c. Degenerate input (too few, non-finite,
// coincident or collinear points) returns a status and finite zero geometry, never NaN.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <iterator>
#include <optional>
#include <vector>

#include "plucker/geometry/plucker_line.h"

namespace plucker {

enum class FitStatus {
  kOk,
  kTooFewPoints,  // plane: < 3, line: < 2
  kNonFinite,     // a coordinate is NaN or infinite
  kDegenerate,    // coincident points (line, plane) or collinear points (plane)
};
const char* ToString(FitStatus status);

struct FitOptions {
  // Points whose spread (largest standard deviation about the centroid, or for three points the
  // shortest edge from the first) is below this many metres count as coincident.
  double min_extent = 1e-9;
  // Plane: points with sqrt(lambda1 / lambda2) (second / largest standard deviation) or, for three
  // points, the sine of the angle at the first point below this count as collinear.
  double min_relative_spread = 1e-7;
};

struct PlaneFit {
  FitStatus status = FitStatus::kTooFewPoints;
  Eigen::Vector4d plane = Eigen::Vector4d::Zero();  // (m, e), |m| = 1 when ok()
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  // Least-squares fits only (zero for PlaneFromPoints):
  Eigen::Vector3d eigenvalues = Eigen::Vector3d::Zero();  // of the covariance (1/N), ascending
  double thickness_ratio = 0.0;   // lambda0 / lambda1 (lambda0 = rms^2): 0 for planar points
  double rms_distance = 0.0;      // RMS of point-plane distances (~ sqrt(lambda0))
  double max_abs_distance = 0.0;  // largest |point-plane distance|
  int num_points = 0;
  bool ok() const { return status == FitStatus::kOk; }
};

struct LineFit {
  FitStatus status = FitStatus::kTooFewPoints;
  Line6d L = Line6d::Zero();  // [n; d], |d| = 1, n = centroid x d, when ok()
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d eigenvalues = Eigen::Vector3d::Zero();  // of the covariance (1/N), ascending
  double linearity_ratio = 0.0;  // lambda1 / lambda2: 0 for exactly collinear points (LOAM
                                 // accepts an edge when lambda2 > 3 lambda1, i.e. ratio < 1/3)
  double rms_distance = 0.0;     // RMS of point-line distances (~ sqrt(lambda0 + lambda1))
  double max_distance = 0.0;     // largest point-line distance
  int num_points = 0;
  bool ok() const { return status == FitStatus::kOk; }
};

// Plane through three points; kDegenerate when they are coincident or collinear. The normal
// follows the right-hand rule: m ~ (p2 - p1) x (p3 - p1).
PlaneFit PlaneFromPoints(const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                         const Eigen::Vector3d& p3, const FitOptions& options = {});

// The smallest or the largest eigenvalue of a symmetric 3x3 matrix (lower triangle read), its unit
// eigenvector (sign arbitrary) and the middle eigenvalue: what a plane fit (normal) or a line fit
// (direction, and the ratio of the two largest spreads) needs. Eigen's closed-form solver computes
// all three eigenvectors through atan2 and sincos; this takes about 60 % of its time (150 vs 230 ns
// a map fit in the LiDAR odometry's profile). The matrix is shifted by its mean eigenvalue and
// scaled; the extreme root of the characteristic cubic is found by Newton's method from a bound on
// its side: for a positive semi-definite matrix (a covariance), every eigenvalue lies in
// [0, trace], which puts a plane's or an edge's root next to the start; other matrices start from
// the general bound. The eigenvector is the longest cross product of two rows of A - lambda I. When
// lambda is not well separated from the other two eigenvalues (the product of the gaps below 1e-4
// of the spread: the cross products then lose precision), or A has three equal eigenvalues, Eigen's
// solver is used (`fallback`). Math and tests: docs/math/projection-triangulation.md,
// fitting_test.cc.
struct ExtremeEigenpair {
  double value = 0.0;   // the smallest or the largest eigenvalue
  double middle = 0.0;  // the middle eigenvalue (~sqrt(eps) of the spread when close to the third)
  Eigen::Vector3d vector = Eigen::Vector3d::Zero();  // unit eigenvector of `value`
  bool fallback = false;                             // from Eigen's solver
};
ExtremeEigenpair SmallestEigenpair(const Eigen::Matrix3d& A);
ExtremeEigenpair LargestEigenpair(const Eigen::Matrix3d& A);

// Signed distance m . p + e of p from a plane with unit normal (as returned by the fits).
inline double PointPlaneDistance(const Eigen::Vector4d& plane, const Eigen::Vector3d& p) {
  return plane.head<3>().dot(p) + plane(3);
}
// (m, e) scaled so that |m| = 1; nullopt for a zero or non-finite normal.
std::optional<Eigen::Vector4d> NormalizePlane(const Eigen::Vector4d& plane);

namespace fitting_internal {
// Moments of the points: count, centroid and covariance (1/N) about the centroid (two passes, no
// allocation). Returns false for a non-finite coordinate.
template <typename It>
bool Moments(It first, It last, int* n, Eigen::Vector3d* centroid, Eigen::Matrix3d* cov) {
  *n = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (It it = first; it != last; ++it) {
    const Eigen::Vector3d p = (*it).template cast<double>();
    if (!p.allFinite()) return false;
    sum += p;
    ++*n;
  }
  if (*n == 0) return true;
  *centroid = sum / *n;
  double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  for (It it = first; it != last; ++it) {
    const Eigen::Vector3d q = (*it).template cast<double>() - *centroid;
    xx += q.x() * q.x();
    xy += q.x() * q.y();
    xz += q.x() * q.z();
    yy += q.y() * q.y();
    yz += q.y() * q.z();
    zz += q.z() * q.z();
  }
  *cov << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  *cov /= *n;
  return true;
}
// The parts that do not depend on the iterator type (fitting.cc); the distance statistics are
// filled by the templates from the points.
PlaneFit PlaneFromMoments(int n, const Eigen::Vector3d& centroid, const Eigen::Matrix3d& cov,
                          const FitOptions& options);
LineFit LineFromMoments(int n, const Eigen::Vector3d& centroid, const Eigen::Matrix3d& cov,
                        const FitOptions& options);
}  // namespace fitting_internal

// Least-squares plane of N >= 3 points: through the centroid, normal = eigenvector of the smallest
// covariance eigenvalue. It = forward iterator over Eigen 3-vectors (double or float).
template <typename It>
PlaneFit FitPlane(It first, It last, const FitOptions& options = {}) {
  int n = 0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  PlaneFit fit;
  if (!fitting_internal::Moments(first, last, &n, &c, &cov)) {
    fit.status = FitStatus::kNonFinite;
    return fit;
  }
  fit = fitting_internal::PlaneFromMoments(n, c, cov, options);
  if (!fit.ok()) return fit;
  // Distances from the points themselves: sqrt(lambda0) is only accurate to ~1e-8 of the spread.
  double sum_sq = 0.0;
  for (It it = first; it != last; ++it) {
    const double dist = std::abs(PointPlaneDistance(fit.plane, (*it).template cast<double>()));
    sum_sq += dist * dist;
    if (dist > fit.max_abs_distance) fit.max_abs_distance = dist;
  }
  fit.rms_distance = std::sqrt(sum_sq / n);
  fit.thickness_ratio = sum_sq / n / fit.eigenvalues(1);
  return fit;
}
inline PlaneFit FitPlane(const std::vector<Eigen::Vector3d>& points,
                         const FitOptions& options = {}) {
  return FitPlane(points.begin(), points.end(), options);
}

// Least-squares line of N >= 2 points: through the centroid along the principal direction.
template <typename It>
LineFit FitLine(It first, It last, const FitOptions& options = {}) {
  int n = 0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  LineFit fit;
  if (!fitting_internal::Moments(first, last, &n, &c, &cov)) {
    fit.status = FitStatus::kNonFinite;
    return fit;
  }
  fit = fitting_internal::LineFromMoments(n, c, cov, options);
  if (!fit.ok()) return fit;
  const Eigen::Vector3d d = fit.L.tail<3>();
  double sum_sq = 0.0;
  for (It it = first; it != last; ++it) {
    const Eigen::Vector3d q = (*it).template cast<double>() - c;
    const double dist = (q - d * d.dot(q)).norm();
    sum_sq += dist * dist;
    if (dist > fit.max_distance) fit.max_distance = dist;
  }
  fit.rms_distance = std::sqrt(sum_sq / n);
  return fit;
}
inline LineFit FitLine(const std::vector<Eigen::Vector3d>& points, const FitOptions& options = {}) {
  return FitLine(points.begin(), points.end(), options);
}

}  // namespace plucker
