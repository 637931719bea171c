// Pinhole projection of 3D points (ideal camera: observations are undistorted beforehand, see
// geometry/distortion.h). Derivations: docs/math/projection-triangulation.md.
//
// Camera pose T_w_c (camera -> world), world point p_w:
//   p_c = T_w_c^-1 p_w = R^T (p_w - t),   uv = (fx x/z + cx, fy y/z + cy).
// Pose Jacobians use the tangent of docs/conventions.md: delta = (dtheta, dt),
// R <- R Exp(dtheta), t <- t + dt.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <optional>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/se3.h"

namespace plucker {

// Camera pose T_w_c, world point p_w. p_c = T_w_c^-1 p_w; pixel = K * (x/z, y/z).
// Returns nullopt when the point is not in front of the camera (z <= min_depth) or input
// non-finite (pose, point or intrinsics). Jacobians: d_uv_d_Twc w.r.t. the pose tangent
// (dtheta, dt), d_uv_d_pw w.r.t. the world point. They are written only on success.
std::optional<Eigen::Vector2d> ProjectPoint(const PinholeIntrinsics& K, const SE3d& T_w_c,
                                            const Eigen::Vector3d& p_w,
                                            Eigen::Matrix<double, 2, 6>* d_uv_d_Twc = nullptr,
                                            Eigen::Matrix<double, 2, 3>* d_uv_d_pw = nullptr,
                                            double min_depth = 1e-6);

// Same from camera coordinates, with d_uv_d_pc (2x3).
std::optional<Eigen::Vector2d> ProjectCameraPoint(const PinholeIntrinsics& K,
                                                  const Eigen::Vector3d& p_c,
                                                  Eigen::Matrix<double, 2, 3>* d_uv_d_pc = nullptr,
                                                  double min_depth = 1e-6);

// Value-only templates (run with ceres::Jet in autodiff twins; same formula as above). Return false
// (and leave *uv untouched) when z <= min_depth. No finiteness check: Jets are checked by callers.
template <typename T>
bool ProjectCameraPointT(const PinholeIntrinsics& K, const Eigen::Matrix<T, 3, 1>& p_c,
                         Eigen::Matrix<T, 2, 1>* uv, double min_depth = 1e-6) {
  if (!(p_c(2) > T(min_depth))) return false;
  const T inv_z = T(1) / p_c(2);
  (*uv)(0) = T(K.fx) * p_c(0) * inv_z + T(K.cx);
  (*uv)(1) = T(K.fy) * p_c(1) * inv_z + T(K.cy);
  return true;
}

template <typename T>
bool ProjectPointT(const PinholeIntrinsics& K, const SE3<T>& T_w_c,
                   const Eigen::Matrix<T, 3, 1>& p_w, Eigen::Matrix<T, 2, 1>* uv,
                   double min_depth = 1e-6) {
  const Eigen::Matrix<T, 3, 1> p_c = T_w_c.rotation().conjugate() * (p_w - T_w_c.translation());
  return ProjectCameraPointT<T>(K, p_c, uv, min_depth);
}

}  // namespace plucker
