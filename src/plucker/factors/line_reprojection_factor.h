// Line reprojection factors (docs/math/lines.md).
//
// Measurement: an image segment with endpoints s_px, e_px (undistorted pixels) and a 2x2 square-
// root information matrix. Residual, with the world line L_w = PluckerFromOrthonormal(line) and the
// camera-frame line L_c:
//   l = K_line n_c,   r = sqrt_information * [s^T l, e^T l] / sqrt(l1^2 + l2^2)   (pixels)
// (signed endpoint-to-line distances, geometry/line_projection.h).
//
//   LineReprojectionFactor    (2 | 7, 6)     parameters T_w_c (pose block), line (line block);
//                                            L_c = TransformLine(T_c_w, L_w).
//   LineReprojectionFactorVI  (2 | 7, 7, 6)  parameters T_w_b, T_b_c (extrinsic), line;
//                                            L_b = TransformLine(T_b_w, L_w),
//                                            L_c = TransformLine(T_c_b, L_b). T_b_c may be held
//                                            constant (jacobians[1] == nullptr is honoured).
//
// Jacobians are written w.r.t. the AMBIENT parameters (7 per pose, 6 for the line): the tangent
// Jacobian from the chain rule r <- l <- L_c <- (poses, L_w) <- (dtheta, dphi), times the
// manifolds' MinusJacobian (pose_block::WriteAmbient, factors/line_manifold.h). This equals the
// exact derivative of the residual with normalised quaternions and W, which is what the autodiff
// twins (CreateAutoDiff, functors below) compute.
//
// Errors: Create/CreateAutoDiff throw std::invalid_argument for invalid intrinsics, non-finite
// endpoints or sqrt_information, or a segment shorter than kMinSegmentLengthPx. Evaluate returns
// false for non-finite parameters, a zero quaternion or zero W, a line passing within
// kMinLineCameraDistance of the camera centre (LineThroughCameraCentre: it projects to a point),
// an image line refused by the guard of EndpointLineResidual (the line lies in the camera's
// principal plane), or a non-finite result.
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/line_projection.h"
#include "plucker/geometry/orthonormal_line.h"
#include "plucker/geometry/se3.h"

namespace plucker {

// Segments shorter than this (pixels) are rejected at construction.
constexpr double kMinSegmentLengthPx = 1e-6;

// The measurement shared by both factors (validated by the constructors).
struct LineSegmentMeasurement {
  Eigen::Matrix3d K_line;
  Eigen::Vector2d s_px;
  Eigen::Vector2d e_px;
  Eigen::Matrix2d sqrt_information;
};

// Throws std::invalid_argument as documented above.
LineSegmentMeasurement MakeLineSegmentMeasurement(const PinholeIntrinsics& K,
                                                  const Eigen::Vector2d& s_px,
                                                  const Eigen::Vector2d& e_px,
                                                  const Eigen::Matrix2d& sqrt_information);

namespace line_factor_internal {
// A pose block with a zero quaternion or a line block with a zero q or W cannot be normalised.
template <typename T>
bool HasZeroQuaternion(const T* p) {
  return !(p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + p[3] * p[3] > T(0));
}
template <typename T>
bool IsDegenerateLineBlock(const T* p) {
  return HasZeroQuaternion(p) || !(p[4] * p[4] + p[5] * p[5] > T(0));
}
}  // namespace line_factor_internal

// Autodiff twins: the same residual written with the templated value functions.

struct LineReprojectionResidual {
  explicit LineReprojectionResidual(const LineSegmentMeasurement& obs) : obs_(obs) {}
  template <typename T>
  bool operator()(const T* T_w_c, const T* line, T* residual) const {
    using namespace line_factor_internal;
    if (HasZeroQuaternion(T_w_c) || IsDegenerateLineBlock(line)) return false;
    const Line6<T> L_w = PluckerFromOrthonormal<T>(line);
    const Line6<T> L_c = TransformLine<T>(SE3<T>::FromParameters(T_w_c).Inverse(), L_w);
    return Finish<T>(L_c, residual);
  }
  template <typename T>
  bool Finish(const Line6<T>& L_c, T* residual) const {
    if (LineThroughCameraCentre<T>(L_c)) return false;
    Eigen::Matrix<T, 2, 1> r;
    if (!EndpointLineResidualT<T>(ProjectLinePixels<T>(obs_.K_line, L_c), obs_.s_px, obs_.e_px,
                                  &r)) {
      return false;
    }
    const Eigen::Matrix<T, 2, 1> weighted = obs_.sqrt_information.cast<T>() * r;
    residual[0] = weighted(0);
    residual[1] = weighted(1);
    return true;
  }
  LineSegmentMeasurement obs_;
};

struct LineReprojectionResidualVI {
  explicit LineReprojectionResidualVI(const LineSegmentMeasurement& obs) : base_(obs) {}
  template <typename T>
  bool operator()(const T* T_w_b, const T* T_b_c, const T* line, T* residual) const {
    using namespace line_factor_internal;
    if (HasZeroQuaternion(T_w_b) || HasZeroQuaternion(T_b_c) || IsDegenerateLineBlock(line)) {
      return false;
    }
    const Line6<T> L_w = PluckerFromOrthonormal<T>(line);
    const Line6<T> L_b = TransformLine<T>(SE3<T>::FromParameters(T_w_b).Inverse(), L_w);
    const Line6<T> L_c = TransformLine<T>(SE3<T>::FromParameters(T_b_c).Inverse(), L_b);
    return base_.Finish<T>(L_c, residual);
  }
  LineReprojectionResidual base_;
};

class LineReprojectionFactor final : public ceres::SizedCostFunction<2, 7, 6> {
 public:
  explicit LineReprojectionFactor(const LineSegmentMeasurement& obs) : obs_(obs) {}

  static ceres::CostFunction* Create(const PinholeIntrinsics& K, const Eigen::Vector2d& s_px,
                                     const Eigen::Vector2d& e_px,
                                     const Eigen::Matrix2d& sqrt_information);
  static ceres::CostFunction* CreateAutoDiff(const PinholeIntrinsics& K,
                                             const Eigen::Vector2d& s_px,
                                             const Eigen::Vector2d& e_px,
                                             const Eigen::Matrix2d& sqrt_information);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  const LineSegmentMeasurement obs_;
};

class LineReprojectionFactorVI final : public ceres::SizedCostFunction<2, 7, 7, 6> {
 public:
  explicit LineReprojectionFactorVI(const LineSegmentMeasurement& obs) : obs_(obs) {}

  static ceres::CostFunction* Create(const PinholeIntrinsics& K, const Eigen::Vector2d& s_px,
                                     const Eigen::Vector2d& e_px,
                                     const Eigen::Matrix2d& sqrt_information);
  static ceres::CostFunction* CreateAutoDiff(const PinholeIntrinsics& K,
                                             const Eigen::Vector2d& s_px,
                                             const Eigen::Vector2d& e_px,
                                             const Eigen::Matrix2d& sqrt_information);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  const LineSegmentMeasurement obs_;
};

}  // namespace plucker
