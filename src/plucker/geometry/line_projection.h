// Projection of Plücker lines into a pinhole camera and the endpoint-to-line residual
// (docs/math/lines.md). Ideal pinhole: observations are undistorted beforehand.
//
// A camera-frame line L_c = [n_c; d_c] projects to the homogeneous image line l (l1 x + l2 y + l3
// = 0): in normalized coordinates l = n_c; in pixels l = K_line n_c with
//   K_line = [[fy, 0, 0], [0, fx, 0], [-fy cx, -fx cy, fx fy]]  (= det(K) K^-T).
// Only the moment matters.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <optional>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/plucker_line.h"

namespace plucker {

// K_line for a zero-skew pinhole camera.
Eigen::Matrix3d LineIntrinsics(const PinholeIntrinsics& K);

// Image line in normalized coordinates: l = n_c (d_l_d_Lc = [I, 0], 3x6).
template <typename T>
Eigen::Matrix<T, 3, 1> ProjectLineNormalized(const Line6<T>& L_c) {
  return L_c.template head<3>();
}

// Image line in pixels: l = K_line n_c (templated value version).
template <typename T>
Eigen::Matrix<T, 3, 1> ProjectLinePixels(const Eigen::Matrix3d& K_line, const Line6<T>& L_c) {
  return K_line.cast<T>() * L_c.template head<3>();
}

// Same with d_l_d_Lc = [K_line, 0] (3x6).
Eigen::Vector3d ProjectLinePixels(const PinholeIntrinsics& K, const Line6d& L_c,
                                  Eigen::Matrix<double, 3, 6>* d_l_d_Lc = nullptr);

// A camera-frame line passing within kMinLineCameraDistance (metres, |n_c|/|d_c|) of the camera
// centre projects to a point: its image line l = K_line n_c is rounding noise, so no relative test
// on l can detect it. Factors refuse such lines with this test before projecting. Also true for
// a zero or non-finite direction.
constexpr double kMinLineCameraDistance = 1e-9;

template <typename T>
bool LineThroughCameraCentre(const Line6<T>& L_c, double min_distance = kMinLineCameraDistance) {
  const T n_sq = L_c.template head<3>().squaredNorm();
  const T d_sq = L_c.template tail<3>().squaredNorm();
  return !(d_sq > T(0)) || !(n_sq > T(min_distance * min_distance) * d_sq);
}

// Guard of the endpoint residual: the residual divides by rho = sqrt(l1^2 + l2^2). It is refused
// when rho <= kMinImageLineNormalRatio * |l|, i.e. when l is (numerically) proportional to
// (0, 0, 1) or zero. For pixel lines |l3|/rho is the distance of the image line from the pixel
// origin, so the guard fires for image lines more than ~1e6 px away: the 3D line passes through
// the camera centre (n_c = 0, it projects to a point) or lies in the camera's principal plane
// z_c = 0 (it projects to the line at infinity). Never divides by ~0.
constexpr double kMinImageLineNormalRatio = 1e-6;

// r = [s^T l, e^T l] / sqrt(l1^2 + l2^2), s and e homogeneous pixels (x, y, 1): the signed
// distances of the segment endpoints from the image line, in pixels. d_r_d_l (2x3):
//   d r_i / d l = x_i^T / rho - (x_i^T l) [l1, l2, 0] / rho^3.
// Returns nullopt under the guard above or for non-finite input (then d_r_d_l is untouched).
std::optional<Eigen::Vector2d> EndpointLineResidual(const Eigen::Vector3d& l_px,
                                                    const Eigen::Vector2d& s_px,
                                                    const Eigen::Vector2d& e_px,
                                                    Eigen::Matrix<double, 2, 3>* d_r_d_l = nullptr);

// Templated value version (for Jets): same formula and guard; returns false under the guard.
template <typename T>
bool EndpointLineResidualT(const Eigen::Matrix<T, 3, 1>& l, const Eigen::Vector2d& s_px,
                           const Eigen::Vector2d& e_px, Eigen::Matrix<T, 2, 1>* r) {
  using std::sqrt;
  const T rho_sq = l(0) * l(0) + l(1) * l(1);
  const T l_sq = rho_sq + l(2) * l(2);
  const double ratio_sq = kMinImageLineNormalRatio * kMinImageLineNormalRatio;
  if (!(rho_sq > T(ratio_sq) * l_sq)) return false;
  const T inv_rho = T(1) / sqrt(rho_sq);
  (*r)(0) = (T(s_px(0)) * l(0) + T(s_px(1)) * l(1) + l(2)) * inv_rho;
  (*r)(1) = (T(e_px(0)) * l(0) + T(e_px(1)) * l(1) + l(2)) * inv_rho;
  return true;
}

}  // namespace plucker
