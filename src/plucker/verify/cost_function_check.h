// Checking a ceres::CostFunction's analytic Jacobians against its autodiff twin (in ambient
// coordinates, <= 1e-9) and against central differences taken through each block's manifold Plus
// (in tangent coordinates, <= 1e-6): the shared body of the factor checks (point_factor_checks.cc,
// lidar_factor_checks.cc).
#pragma once

#include <ceres/cost_function.h>
#include <ceres/manifold.h>

#include <Eigen/Core>
#include <string>
#include <vector>

#include "plucker/verify/jacobian_check.h"

namespace plucker {
namespace verify {

// Residual and ambient Jacobians (rows = residuals, cols = block size) of f at the blocks x.
// Returns false when Evaluate fails or produces non-finite values.
bool EvaluateCostFunction(const ceres::CostFunction& f, const std::vector<Eigen::VectorXd>& x,
                          Eigen::VectorXd* residual, std::vector<Eigen::MatrixXd>* jacobians);

// One sample: analytic vs autodiff (ambient, concatenated over blocks) and analytic * PlusJacobian
// vs central differences of the analytic residual through manifold Plus (tangent). manifolds[i]
// may be nullptr for a Euclidean block. Returns false (and records nothing) when either cost
// function refuses to evaluate at x; the caller counts it as skipped.
bool AddCostFunctionSample(const ceres::CostFunction& analytic, const ceres::CostFunction& autodiff,
                           const std::vector<const ceres::Manifold*>& manifolds,
                           const std::vector<Eigen::VectorXd>& x, JacobianCheckStats* stats,
                           const std::string& what = "", double h = 1e-6);

}  // namespace verify
}  // namespace plucker
