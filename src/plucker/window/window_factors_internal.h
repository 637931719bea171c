// Private to the window layer (not installed): the small residuals the sliding window adds to
// the verified factors of factors/ (pose and vector priors, the zero-motion factor of a standing
// body) and the first-estimate-Jacobian wrapper. Autodiff only: each is a few lines of algebra
// on the PoseManifold tangent, and Ceres differentiates them.
#pragma once

#include <ceres/cost_function.h>

#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "plucker/geometry/se3.h"
#include "plucker/geometry/so3.h"

namespace plucker {
namespace window {
namespace internal {

// r = S * Minus(T_w_c, prior) on the PoseManifold tangent.
struct PosePriorResidual {
  SE3d prior;
  Eigen::Matrix<double, 6, 6> S;
  template <typename T>
  bool operator()(const T* x, T* residual) const {
    // The rotation difference in the hemisphere of the prior's quaternion (q and -q are one
    // rotation; the prior may come with either sign).
    const SE3<T> X = SE3<T>::FromParameters(x);
    Eigen::Quaternion<T> dq = prior.rotation().cast<T>().conjugate() * X.rotation();
    if (dq.w() < T(0)) dq.coeffs() = -dq.coeffs();
    Eigen::Matrix<T, 6, 1> d;
    d.template head<3>() = LogUnitQuaternion<T>(dq);
    d.template tail<3>() = X.translation() - prior.translation().cast<T>();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r = S.cast<T>() * d;
    return true;
  }
};

// First-estimate Jacobians: the residual at the current values, the Jacobians with the blocks that
// have a first estimate replaced by it (falls back to the current values if that fails).
class FirstEstimateCost final : public ceres::CostFunction {
 public:
  FirstEstimateCost(ceres::CostFunction* inner, std::vector<const double*> first_estimates)
      : inner_(inner), fe_(std::move(first_estimates)) {
    set_num_residuals(inner->num_residuals());
    *mutable_parameter_block_sizes() = inner->parameter_block_sizes();
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    if (jacobians == nullptr) return inner_->Evaluate(parameters, residuals, nullptr);
    if (!inner_->Evaluate(parameters, residuals, nullptr)) return false;
    // On the stack for the window's factors (at most 6 blocks, 15 residuals: the IMU factor).
    constexpr std::size_t kMaxBlocks = 8, kMaxResiduals = 16;
    std::array<const double*, kMaxBlocks> at_fe_small;
    std::array<double, kMaxResiduals> scratch_small;
    std::vector<const double*> at_fe_large;
    std::vector<double> scratch_large;
    const double** at_fe = at_fe_small.data();
    double* scratch = scratch_small.data();
    if (fe_.size() > kMaxBlocks) {
      at_fe_large.resize(fe_.size());
      at_fe = at_fe_large.data();
    }
    if (static_cast<std::size_t>(num_residuals()) > kMaxResiduals) {
      scratch_large.resize(num_residuals());
      scratch = scratch_large.data();
    }
    for (std::size_t i = 0; i < fe_.size(); ++i)
      at_fe[i] = fe_[i] != nullptr ? fe_[i] : parameters[i];
    if (inner_->Evaluate(at_fe, scratch, jacobians)) return true;
    return inner_->Evaluate(parameters, scratch, jacobians);
  }

 private:
  std::unique_ptr<ceres::CostFunction> inner_;
  std::vector<const double*> fe_;
};

// r = S (x - x0) on a vector block (the inertial priors on a velocity or a bias block).
template <int kN>
struct VectorPriorResidual {
  Eigen::Matrix<double, kN, 1> x0;
  Eigen::Matrix<double, kN, kN> S;
  template <typename T>
  bool operator()(const T* x, T* residual) const {
    Eigen::Map<Eigen::Matrix<T, kN, 1>> r(residual);
    r = S.template cast<T>() *
        (Eigen::Map<const Eigen::Matrix<T, kN, 1>>(x) - x0.template cast<T>());
    return true;
  }
};

// Zero motion between two keyframes of a standing body (9 | 7 T_w_b_i, 7 T_w_b_j, 3 v_j):
// r = [Log(R_i^T R_j) / sigma_R, (p_j - p_i) / sigma_p, v_j / sigma_v].
struct ZeroMotionResidual {
  double sigma_R, sigma_p, sigma_v;
  template <typename T>
  bool operator()(const T* pose_i, const T* pose_j, const T* v_j, T* residual) const {
    const SE3<T> Ti = SE3<T>::FromParameters(pose_i), Tj = SE3<T>::FromParameters(pose_j);
    Eigen::Quaternion<T> dq = Ti.rotation().conjugate() * Tj.rotation();
    if (dq.w() < T(0)) dq.coeffs() = -dq.coeffs();
    Eigen::Map<Eigen::Matrix<T, 9, 1>> r(residual);
    r.template head<3>() = LogUnitQuaternion<T>(dq) / T(sigma_R);
    r.template segment<3>(3) = (Tj.translation() - Ti.translation()) / T(sigma_p);
    r.template tail<3>() = Eigen::Map<const Eigen::Matrix<T, 3, 1>>(v_j) / T(sigma_v);
    return true;
  }
};

}  // namespace internal
}  // namespace window
}  // namespace plucker
