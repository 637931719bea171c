// Radial-tangential ("plumb bob", OpenCV/KITTI) lens distortion on normalized image coordinates.
// Observations are undistorted once, before they reach the residuals (which use the ideal pinhole
// of geometry/camera.h). Derivations: docs/math/projection-triangulation.md.
//
// For an ideal normalized point x = (x, y), r2 = x^2 + y^2:
//   radial = 1 + k1 r2 + k2 r2^2 + k3 r2^3
//   xd = x radial + 2 p1 x y + p2 (r2 + 2 x^2)
//   yd = y radial + p1 (r2 + 2 y^2) + 2 p2 x y
//
// Valid region of Undistort: the distortion map is inverted by Gauss-Newton started at x = xd. The
// answer is accepted only when the residual |D(x) - xd| falls below the tolerance, det(dD/dx) stays
// above min_jacobian_det along the iterations and at the solution (so the solution lies in the
// region around the principal point where D is a local diffeomorphism: beyond the first circle
// where det(dD/dx) = 0, strong barrel distortion folds back and the inverse is ambiguous), and the
// radial factor is positive. Anything else returns nullopt: outside the image of that region, or
// for non-finite input.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <optional>
#include <utility>

#include "plucker/geometry/camera.h"

namespace plucker {

struct RadTanDistortion {
  double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0;

  bool IsValid() const {
    return std::isfinite(k1) && std::isfinite(k2) && std::isfinite(p1) && std::isfinite(p2) &&
           std::isfinite(k3);
  }
  bool IsZero() const { return k1 == 0 && k2 == 0 && p1 == 0 && p2 == 0 && k3 == 0; }
};

// Value-only distortion (templated for ceres::Jet).
template <typename T>
Eigen::Matrix<T, 2, 1> DistortT(const RadTanDistortion& D, const Eigen::Matrix<T, 2, 1>& xn) {
  const T x = xn(0), y = xn(1);
  const T r2 = x * x + y * y;
  const T radial = T(1) + r2 * (T(D.k1) + r2 * (T(D.k2) + r2 * T(D.k3)));
  return Eigen::Matrix<T, 2, 1>(x * radial + T(2 * D.p1) * x * y + T(D.p2) * (r2 + T(2) * x * x),
                                y * radial + T(D.p1) * (r2 + T(2) * y * y) + T(2 * D.p2) * x * y);
}

// Distorted normalized coordinates of the ideal normalized point xn, with the 2x2 Jacobian
// d_xd_d_xn. No finiteness check (a pure polynomial).
Eigen::Vector2d Distort(const RadTanDistortion& D, const Eigen::Vector2d& xn,
                        Eigen::Matrix2d* d_xd_d_xn = nullptr);

struct UndistortOptions {
  int max_iterations = 30;         // Gauss-Newton iterations before giving up
  double tolerance = 1e-12;        // accept when |D(x) - xd| < tolerance (normalized units)
  double min_jacobian_det = 1e-3;  // det(dD/dx) must stay above this (valid region, see top)
};

// Ideal normalized point x with Distort(x) == xd, or nullopt (see "valid region" above).
std::optional<Eigen::Vector2d> Undistort(const RadTanDistortion& D, const Eigen::Vector2d& xd,
                                         const UndistortOptions& options = {});

// Pixel versions: distorted pixel -> ideal pixel (same K), and back.
std::optional<Eigen::Vector2d> UndistortPixel(const PinholeIntrinsics& K, const RadTanDistortion& D,
                                              const Eigen::Vector2d& uv_distorted,
                                              const UndistortOptions& options = {});
std::optional<Eigen::Vector2d> DistortPixel(const PinholeIntrinsics& K, const RadTanDistortion& D,
                                            const Eigen::Vector2d& uv_ideal);

// Both endpoints of an observed segment (distorted pixels) -> ideal pixels; nullopt when either
// endpoint fails. Note: a distorted straight edge is curved in the image; undistorting its two
// endpoints gives the ideal chord, which is exact for the line through them.
std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>> UndistortSegment(
    const PinholeIntrinsics& K, const RadTanDistortion& D, const Eigen::Vector2d& start_distorted,
    const Eigen::Vector2d& end_distorted, const UndistortOptions& options = {});

}  // namespace plucker
