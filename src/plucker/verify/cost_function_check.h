// Checking a ceres::CostFunction's analytic Jacobians against its autodiff twin (in ambient
// coordinates, <= 1e-9) and against central differences taken through each block's manifold Plus,
// extrapolated by Ridders' method (in tangent coordinates, <= 1e-6; they reach ~1e-10, where a
// fixed step reached ~1e-6 and failed on far lines now and then): the one sampling loop of the
// factor checks (line_factor_checks.cc, point_factor_checks.cc, lidar_factor_checks.cc).
#pragma once

#include <ceres/cost_function.h>
#include <ceres/manifold.h>

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "plucker/verify/jacobian_check.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace verify {

// One configuration of a cost function: both versions, the parameter blocks and how to difference
// them.
struct CostFunctionSample {
  std::unique_ptr<ceres::CostFunction> analytic, autodiff;
  std::vector<Eigen::VectorXd> x;
  // Per block: the manifold whose Plus the central differences go through; nullptr differences
  // the raw (ambient) parameters.
  std::vector<const ceres::Manifold*> manifolds;
  // Per block finest step of Ridders' tableau (which starts at 100 x this); empty: 1e-6.
  std::vector<double> steps;
  // The residual comparison is relative to max(|r|, residual_scale): raise it where the residual
  // is a difference of large terms (rounding grows with them).
  double residual_scale = 1.0;
  std::string what;             // describes the configuration in the failure message
  bool expect_refusal = false;  // a guarded configuration: both versions must refuse it
  // What the factors were made from, for JacobianCheckOptions::factor_sample_observer.
  std::vector<std::pair<std::string, Eigen::VectorXd>> inputs;
};

// Residual and ambient Jacobians (rows = residuals, cols = block size) of f at the blocks x.
// Returns false when Evaluate fails or produces non-finite values.
bool EvaluateCostFunction(const ceres::CostFunction& f, const std::vector<Eigen::VectorXd>& x,
                          Eigen::VectorXd* residual, std::vector<Eigen::MatrixXd>* jacobians);

// The check `name` over make(rng, 0), make(rng, 1), ... (rng seeded with o.seed + seed_offset)
// until o.samples were compared. Each sample compares analytic and autodiff (residual and ambient
// Jacobian, concatenated over blocks) and analytic * PlusJacobian with Ridders-extrapolated central
// differences of the analytic residual through Plus. An expected refusal by both versions counts as
// skipped; any other refusal (by one version only, of an unguarded configuration, or of Plus /
// PlusJacobian) is a failed sample.
JacobianCheckStats RunCostFunctionCheck(const std::string& name, std::uint64_t seed_offset,
                                        const JacobianCheckOptions& o,
                                        const std::function<CostFunctionSample(Rng&, int)>& make);

}  // namespace verify
}  // namespace plucker
