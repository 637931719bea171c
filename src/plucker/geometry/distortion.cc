#include "plucker/geometry/distortion.h"

#include <Eigen/LU>

namespace plucker {

Eigen::Vector2d Distort(const RadTanDistortion& D, const Eigen::Vector2d& xn,
                        Eigen::Matrix2d* d_xd_d_xn) {
  if (d_xd_d_xn) {
    const double x = xn.x(), y = xn.y();
    const double r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (D.k1 + r2 * (D.k2 + r2 * D.k3));
    // d radial / d r2.
    const double dradial = D.k1 + r2 * (2.0 * D.k2 + 3.0 * r2 * D.k3);
    const double cross = 2.0 * x * y * dradial;
    (*d_xd_d_xn)(0, 0) = radial + 2.0 * x * x * dradial + 2.0 * D.p1 * y + 6.0 * D.p2 * x;
    (*d_xd_d_xn)(0, 1) = cross + 2.0 * D.p1 * x + 2.0 * D.p2 * y;
    (*d_xd_d_xn)(1, 0) = cross + 2.0 * D.p1 * x + 2.0 * D.p2 * y;
    (*d_xd_d_xn)(1, 1) = radial + 2.0 * y * y * dradial + 6.0 * D.p1 * y + 2.0 * D.p2 * x;
  }
  return DistortT<double>(D, xn);
}

std::optional<Eigen::Vector2d> Undistort(const RadTanDistortion& D, const Eigen::Vector2d& xd,
                                         const UndistortOptions& options) {
  if (!D.IsValid() || !xd.allFinite()) return std::nullopt;
  if (D.IsZero()) return xd;
  Eigen::Vector2d x = xd;
  for (int it = 0; it <= options.max_iterations; ++it) {
    Eigen::Matrix2d J;
    const Eigen::Vector2d r = Distort(D, x, &J) - xd;
    const double det = J.determinant();
    if (!r.allFinite() || !(det > options.min_jacobian_det)) return std::nullopt;
    if (r.norm() < options.tolerance) {
      const double r2 = x.squaredNorm();
      const double radial = 1.0 + r2 * (D.k1 + r2 * (D.k2 + r2 * D.k3));
      if (!(radial > 0.0)) return std::nullopt;
      return x;
    }
    if (it == options.max_iterations) break;
    // Gauss-Newton (= Newton for a square system): x <- x - J^-1 r, halving the step while it
    // does not decrease the residual (guards against overshoot under strong distortion).
    const Eigen::Vector2d step = J.inverse() * r;
    double alpha = 1.0;
    for (int k = 0; k < 10; ++k, alpha *= 0.5) {
      if ((Distort(D, x - alpha * step) - xd).norm() < r.norm()) break;
    }
    x -= alpha * step;
  }
  return std::nullopt;
}

std::optional<Eigen::Vector2d> UndistortPixel(const PinholeIntrinsics& K, const RadTanDistortion& D,
                                              const Eigen::Vector2d& uv_distorted,
                                              const UndistortOptions& options) {
  if (!K.IsValid()) return std::nullopt;
  const auto xn = Undistort(D, K.ToNormalized<double>(uv_distorted), options);
  if (!xn) return std::nullopt;
  return K.ToPixel<double>(*xn);
}

std::optional<Eigen::Vector2d> DistortPixel(const PinholeIntrinsics& K, const RadTanDistortion& D,
                                            const Eigen::Vector2d& uv_ideal) {
  if (!K.IsValid() || !D.IsValid() || !uv_ideal.allFinite()) return std::nullopt;
  const Eigen::Vector2d uv = K.ToPixel<double>(Distort(D, K.ToNormalized<double>(uv_ideal)));
  if (!uv.allFinite()) return std::nullopt;
  return uv;
}

std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>> UndistortSegment(
    const PinholeIntrinsics& K, const RadTanDistortion& D, const Eigen::Vector2d& start_distorted,
    const Eigen::Vector2d& end_distorted, const UndistortOptions& options) {
  const auto s = UndistortPixel(K, D, start_distorted, options);
  if (!s) return std::nullopt;
  const auto e = UndistortPixel(K, D, end_distorted, options);
  if (!e) return std::nullopt;
  return std::make_pair(*s, *e);
}

}  // namespace plucker
