#include "plucker/geometry/equidistant.h"

#include <algorithm>

namespace plucker {

double EquidistantValidTheta(const EquidistantDistortion& D, const EquidistantOptions& options) {
  if (!D.IsValid() || !(options.max_theta > 0.0)) return 0.0;
  const double t_max = std::min(options.max_theta, M_PI);
  // d theta_d / d theta >= 1 - sum (2i + 1) |k_i| u^i for theta^2 <= u = t_max^2.
  const double u = t_max * t_max;
  const double bound =
      1.0 -
      u * (3.0 * std::abs(D.k1) +
           u * (5.0 * std::abs(D.k2) + u * (7.0 * std::abs(D.k3) + u * 9.0 * std::abs(D.k4))));
  if (bound > options.min_derivative) return t_max;
  // Otherwise walk u = theta^2 up from 0 in steps that cannot cross the first u where
  // P(u) = d theta_d / d theta reaches the minimum: with L >= |dP/du| on [0, u_max], P stays
  // above P(u) - L h over a step h, so h = (P(u) - min) / L is safe. The walk ends at the crossing
  // (to 1e-12 in P; one step when P is linear), at u_max, or after 10^4 steps at a double root
  // (a conservative answer).
  const double L =
      3.0 * std::abs(D.k1) +
      u * (10.0 * std::abs(D.k2) + u * (21.0 * std::abs(D.k3) + u * 36.0 * std::abs(D.k4)));
  double v = 0.0;
  for (int i = 0; i < 10000; ++i) {
    const double margin = D.ThetaDDerivative(std::sqrt(v)) - options.min_derivative;
    if (!(margin > 1e-12)) break;
    v += margin / L;
    if (v >= u) return t_max;
  }
  return std::sqrt(v);
}

std::optional<Eigen::Vector2d> EquidistantProject(const EquidistantDistortion& D,
                                                  const Eigen::Vector3d& p_c,
                                                  Eigen::Matrix<double, 2, 3>* d_xd_d_p,
                                                  const EquidistantOptions& options) {
  if (!p_c.allFinite() || !D.IsValid()) return std::nullopt;
  const double x = p_c.x(), y = p_c.y(), z = p_c.z();
  const double r2 = x * x + y * y;
  const double r = std::sqrt(r2);
  const double rho = std::sqrt(r2 + z * z);
  if (!(rho > 0.0) || !std::isfinite(rho)) return std::nullopt;
  const double theta = std::atan2(r, z);
  if (!(theta <= EquidistantValidTheta(D, options))) return std::nullopt;
  const double t2 = theta * theta;
  const double g = 1.0 + t2 * (D.k1 + t2 * (D.k2 + t2 * (D.k3 + t2 * D.k4)));  // theta_d / theta
  // xd = s (x, y) with s = theta_d / r; q = (d s / d r) / r (see docs/math.md).
  double s, q;
  if (theta < 1e-6) {  // z > 0: series in theta, exact on the axis (relative error < 1e-23)
    s = g * (1.0 + t2 / 6.0) / rho;
    q = (2.0 * D.k1 - 2.0 / 3.0) / (rho * rho * rho);
  } else {
    if (!(r > 0.0)) return std::nullopt;  // theta = pi: behind the camera on the axis
    const double sin_t = r / rho, cos_t = z / rho;
    s = theta * g / r;
    q = (D.ThetaDDerivative(theta) * sin_t * cos_t - theta * g) /
        (rho * rho * rho * sin_t * sin_t * sin_t);
  }
  if (d_xd_d_p) {
    const double dz = -D.ThetaDDerivative(theta) / (rho * rho);  // (d s / d z)
    *d_xd_d_p << s + x * x * q, x * y * q, x * dz, x * y * q, s + y * y * q, y * dz;
  }
  const Eigen::Vector2d xd(s * x, s * y);
  if (!xd.allFinite()) return std::nullopt;
  return xd;
}

std::optional<Eigen::Vector3d> EquidistantUnprojectBearing(const EquidistantDistortion& D,
                                                           const Eigen::Vector2d& xd,
                                                           const EquidistantOptions& options) {
  if (!xd.allFinite() || !D.IsValid()) return std::nullopt;
  const double theta_d = xd.norm();
  if (theta_d == 0.0) return Eigen::Vector3d(0, 0, 1);
  const double theta_valid = EquidistantValidTheta(D, options);
  // Outside the field of view (a relative 4e-16 of slack for the rounding of xd at its edge).
  if (!(theta_d <= D.ThetaD(theta_valid) * (1.0 + 4e-16))) return std::nullopt;
  // theta_d(theta) is increasing on [0, theta_valid]: Newton kept inside the bracket [lo, hi]
  // (bisection when a step leaves it), until the step vanishes.
  double lo = 0.0, hi = theta_valid, theta = std::min(theta_d, theta_valid);
  double f = D.ThetaD(theta) - theta_d;
  for (int it = 0; it < options.max_iterations && f != 0.0; ++it) {
    (f > 0.0 ? hi : lo) = theta;
    double next = theta - f / D.ThetaDDerivative(theta);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const double step = std::abs(next - theta);
    theta = next;
    f = D.ThetaD(theta) - theta_d;
    if (step <= 1e-16 * std::max(1.0, theta)) break;
  }
  if (!(std::abs(f) < options.tolerance)) return std::nullopt;
  const double sin_t = std::sin(theta);
  return Eigen::Vector3d(sin_t * xd.x() / theta_d, sin_t * xd.y() / theta_d, std::cos(theta));
}

std::optional<Eigen::Vector2d> EquidistantUndistort(const EquidistantDistortion& D,
                                                    const Eigen::Vector2d& xd,
                                                    const EquidistantOptions& options) {
  const auto bearing = EquidistantUnprojectBearing(D, xd, options);
  if (!bearing || !(bearing->z() > 0.0)) return std::nullopt;
  const Eigen::Vector2d xn = bearing->head<2>() / bearing->z();
  if (!xn.allFinite()) return std::nullopt;
  return xn;
}

}  // namespace plucker
