// Equidistant (Kannala-Brandt) fisheye lens model with four coefficients: Kalibr's `pinhole-equi`
// (`distortion_model: equidistant`, `distortion_coeffs: [k1, k2, k3, k4]`), OpenCV's cv::fisheye.
// It maps a camera-frame point p = (x, y, z) to distorted normalized coordinates xd (pixels are
// K * xd, geometry/camera.h). With r = |(x, y)| and the angle of incidence theta = atan2(r, z):
//   theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8)
//   xd = theta_d * (x, y) / r              (xd = 0 on the optical axis, r = 0)
// All zero coefficients are the ideal equidistant ("f-theta") lens, not a pinhole.
// Derivations: docs/math.md (section "Equidistant camera").
//
// Valid region (the refusal rule): theta in [0, theta_valid], where theta_valid is the smaller
// of options.max_theta and the first angle at which d theta_d / d theta falls to
// options.min_derivative. On that interval theta_d is strictly increasing, so the inverse
// (theta from theta_d) is unique and Newton's method bracketed in [0, theta_valid] converges;
// beyond it a strongly negative k folds the image back onto itself (two angles for one radius)
// and both directions refuse. max_theta defaults to pi/2 (a 180 deg field of view, points with
// z > 0: what the pinhole-based estimators handle); a lens wider than 180 deg (TUM-VI's 195 deg)
// may raise it towards pi for bearing-only use (EquidistantUnprojectBearing).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <optional>

namespace plucker {

struct EquidistantDistortion {
  double k1 = 0.0, k2 = 0.0, k3 = 0.0, k4 = 0.0;

  bool IsValid() const {
    return std::isfinite(k1) && std::isfinite(k2) && std::isfinite(k3) && std::isfinite(k4);
  }
  // theta_d(theta) and its derivative d theta_d / d theta.
  template <typename T>
  T ThetaD(const T& theta) const {
    const T t2 = theta * theta;
    return theta * (T(1) + t2 * (T(k1) + t2 * (T(k2) + t2 * (T(k3) + t2 * T(k4)))));
  }
  double ThetaDDerivative(double theta) const {
    const double t2 = theta * theta;
    return 1.0 + t2 * (3.0 * k1 + t2 * (5.0 * k2 + t2 * (7.0 * k3 + t2 * 9.0 * k4)));
  }
};

struct EquidistantOptions {
  double max_theta = M_PI / 2;   // largest angle of incidence accepted (rad), <= pi
  double min_derivative = 1e-3;  // d theta_d / d theta must stay above this (valid region)
  int max_iterations = 60;       // Newton / bisection steps of the inverse
  double tolerance = 1e-12;      // accept the inverse when |theta_d(theta) - theta_d| < this
};

// theta_valid of the top comment: options.max_theta when the derivative provably stays above
// min_derivative up to it (a bound on the coefficients' magnitudes, no search), otherwise the
// first crossing, found by steps in theta^2 that a Lipschitz bound keeps from passing it (one
// step for k1 alone; a few tens for real lenses). Non-finite coefficients: 0.
double EquidistantValidTheta(const EquidistantDistortion& D,
                             const EquidistantOptions& options = {});

// Distorted normalized coordinates of the camera-frame point p_c with the 2x3 Jacobian
// d_xd_d_p; nullopt when p_c is not finite, is the camera centre, or its theta exceeds
// EquidistantValidTheta. Exact on the optical axis (r = 0: xd = 0, d xd / d(x, y) = I / z).
std::optional<Eigen::Vector2d> EquidistantProject(const EquidistantDistortion& D,
                                                  const Eigen::Vector3d& p_c,
                                                  Eigen::Matrix<double, 2, 3>* d_xd_d_p = nullptr,
                                                  const EquidistantOptions& options = {});

// The same value without checks, templated for ceres::Jet (the autodiff twin). Smooth through
// the optical axis: theta / r is evaluated as a series in r^2 / z^2 near it (z > 0).
template <typename T>
Eigen::Matrix<T, 2, 1> EquidistantProjectT(const EquidistantDistortion& D,
                                           const Eigen::Matrix<T, 3, 1>& p) {
  using std::atan2;
  using std::sqrt;
  const T r2 = p(0) * p(0) + p(1) * p(1);
  T theta_over_r;
  if (p(2) > T(0) && r2 < T(1e-2) * p(2) * p(2)) {
    // atan(t) / t = sum (-u)^n / (2n + 1), u = t^2 = r^2 / z^2 < 0.01: 12 terms reach 1e-25.
    const T u = r2 / (p(2) * p(2));
    T series = T(1.0 / 23.0);
    for (int n = 10; n >= 0; --n) series = T(1.0 / (2 * n + 1)) - u * series;
    theta_over_r = series / p(2);
  } else {
    const T r = sqrt(r2);
    theta_over_r = atan2(r, p(2)) / r;
  }
  const T theta2 = theta_over_r * theta_over_r * r2;
  const T g =
      T(1) + theta2 * (T(D.k1) + theta2 * (T(D.k2) + theta2 * (T(D.k3) + theta2 * T(D.k4))));
  const T s = g * theta_over_r;  // theta_d / r
  return Eigen::Matrix<T, 2, 1>(s * p(0), s * p(1));
}

// The unit bearing (camera frame) whose projection is xd, or nullopt when xd is not finite or
// |xd| > theta_d(theta_valid) (outside the valid field of view).
std::optional<Eigen::Vector3d> EquidistantUnprojectBearing(const EquidistantDistortion& D,
                                                           const Eigen::Vector2d& xd,
                                                           const EquidistantOptions& options = {});

// The ideal normalized point (x / z, y / z) of xd: the bearing above divided by its z; nullopt
// also when its angle of incidence is not below pi/2 (no normalized coordinates).
std::optional<Eigen::Vector2d> EquidistantUndistort(const EquidistantDistortion& D,
                                                    const Eigen::Vector2d& xd,
                                                    const EquidistantOptions& options = {});

}  // namespace plucker
