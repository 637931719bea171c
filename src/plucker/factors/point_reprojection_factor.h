// Point reprojection factors (docs/math/lidar-and-point-factors.md).
//
// Measurement: an undistorted pixel uv and a 2x2 square-root information matrix S. Residual:
//   PointReprojectionFactor    (2 | 7, 3)     parameters T_w_c (pose block), p_w (3-vector):
//                                             r = S (pi(K, T_w_c^-1 p_w) - uv)
//   PointReprojectionFactorVI  (2 | 7, 7, 3)  parameters T_w_b, T_b_c (extrinsic), p_w:
//                                             r = S (pi(K, (T_w_b T_b_c)^-1 p_w) - uv)
//                                             T_b_c may be held constant (jacobians[1] == nullptr
//                                             is honoured).
// pi is the ideal pinhole projection of geometry/point_projection.h.
//
// Jacobians: the tangent Jacobian by the chain rule r <- uv <- p_c <- (poses, p_w), then
// J_ambient = J_tangent * PoseManifold::MinusJacobian(x) for each pose block (the exact derivative
// of the residual with normalised quaternions, which is what the autodiff twins compute).
//
// Errors: Create/CreateAutoDiff throw std::invalid_argument for invalid intrinsics (non-finite or
// non-positive focal length) and non-finite uv or sqrt_information. Evaluate returns false for
// non-finite parameters, a zero quaternion, or a point not in front of the camera
// (depth <= kPointMinDepth).
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/point_projection.h"
#include "plucker/geometry/se3.h"

namespace plucker {

// Points at camera depth <= this [m] are refused (Evaluate returns false).
constexpr double kPointMinDepth = 1e-6;

// The validated measurement shared by both factors.
struct PointObservation {
  PinholeIntrinsics K;
  Eigen::Vector2d uv;
  Eigen::Matrix2d sqrt_information;
};

// Throws std::invalid_argument as documented above.
PointObservation MakePointObservation(const PinholeIntrinsics& K, const Eigen::Vector2d& uv,
                                      const Eigen::Matrix2d& sqrt_information);

// Autodiff twins: the same residual with templated value functions.
struct PointReprojectionResidual {
  PointObservation obs;
  template <typename T>
  bool Finish(const SE3<T>& T_w_c, const T* p_w, T* residual) const {
    Eigen::Matrix<T, 2, 1> uv;
    if (!ProjectPointT<T>(obs.K, T_w_c, Eigen::Matrix<T, 3, 1>(p_w[0], p_w[1], p_w[2]), &uv,
                          kPointMinDepth)) {
      return false;
    }
    const Eigen::Matrix<T, 2, 1> r = obs.sqrt_information.cast<T>() * (uv - obs.uv.cast<T>());
    residual[0] = r(0);
    residual[1] = r(1);
    return true;
  }
  template <typename T>
  bool operator()(const T* T_w_c, const T* p_w, T* residual) const {
    return Finish<T>(SE3<T>::FromParameters(T_w_c), p_w, residual);
  }
};

struct PointReprojectionResidualVI {
  PointReprojectionResidual base;
  template <typename T>
  bool operator()(const T* T_w_b, const T* T_b_c, const T* p_w, T* residual) const {
    return base.Finish<T>(SE3<T>::FromParameters(T_w_b) * SE3<T>::FromParameters(T_b_c), p_w,
                          residual);
  }
};

class PointReprojectionFactor final : public ceres::SizedCostFunction<2, 7, 3> {
 public:
  static ceres::CostFunction* Create(const PinholeIntrinsics& K, const Eigen::Vector2d& uv,
                                     const Eigen::Matrix2d& sqrt_information);
  static ceres::CostFunction* CreateAutoDiff(const PinholeIntrinsics& K, const Eigen::Vector2d& uv,
                                             const Eigen::Matrix2d& sqrt_information);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  explicit PointReprojectionFactor(const PointObservation& obs) : obs_(obs) {}
  const PointObservation obs_;
};

class PointReprojectionFactorVI final : public ceres::SizedCostFunction<2, 7, 7, 3> {
 public:
  static ceres::CostFunction* Create(const PinholeIntrinsics& K, const Eigen::Vector2d& uv,
                                     const Eigen::Matrix2d& sqrt_information);
  static ceres::CostFunction* CreateAutoDiff(const PinholeIntrinsics& K, const Eigen::Vector2d& uv,
                                             const Eigen::Matrix2d& sqrt_information);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  explicit PointReprojectionFactorVI(const PointObservation& obs) : obs_(obs) {}
  const PointObservation obs_;
};

}  // namespace plucker
