// A visual-inertial factor (2 | 7 T_w_b, 7 T_b_c, kN) with the camera-body extrinsic held at a
// given value: a (2 | 7 T_w_b, kN) cost function that evaluates the factor with the extrinsic's
// Jacobian not requested (factors/point_reprojection_factor.h PointReprojectionFactorVI: kN = 3;
// factors/anchored_line_factor.h AnchoredLineFactorVI: kN = 6). The window builds its visual
// factors this way when the extrinsic is not estimated. HeldExtrinsicTimeOffsetFactor does the
// same for the time-offset factors of factors/time_offset_factor.h: (2 | 7 T_w_b, 1 td, kN) from
// (2 | 7 T_w_b, 7 T_b_c, 1 td, kN).
#pragma once

#include <ceres/sized_cost_function.h>

#include <memory>

#include "plucker/geometry/se3.h"

namespace plucker {

template <int kN>
class HeldExtrinsicFactor final : public ceres::SizedCostFunction<2, 7, kN> {
 public:
  // Takes ownership of `vi` (parameter blocks 7, 7, kN).
  HeldExtrinsicFactor(ceres::CostFunction* vi, const SE3d& T_b_c) : vi_(vi) {
    T_b_c.ToParameters(T_b_c_);
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* p[3] = {parameters[0], T_b_c_, parameters[1]};
    double* j[3] = {jacobians ? jacobians[0] : nullptr, nullptr,
                    jacobians ? jacobians[1] : nullptr};
    return vi_->Evaluate(p, residuals, jacobians ? j : nullptr);
  }

 private:
  std::unique_ptr<ceres::CostFunction> vi_;
  double T_b_c_[7];
};

template <int kN>
class HeldExtrinsicTimeOffsetFactor final : public ceres::SizedCostFunction<2, 7, 1, kN> {
 public:
  // Takes ownership of `vi` (parameter blocks 7, 7, 1, kN).
  HeldExtrinsicTimeOffsetFactor(ceres::CostFunction* vi, const SE3d& T_b_c) : vi_(vi) {
    T_b_c.ToParameters(T_b_c_);
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* p[4] = {parameters[0], T_b_c_, parameters[1], parameters[2]};
    double* j[4] = {jacobians ? jacobians[0] : nullptr, nullptr, jacobians ? jacobians[1] : nullptr,
                    jacobians ? jacobians[2] : nullptr};
    return vi_->Evaluate(p, residuals, jacobians ? j : nullptr);
  }

 private:
  std::unique_ptr<ceres::CostFunction> vi_;
  double T_b_c_[7];
};

}  // namespace plucker
