// Shared machinery for proving analytic Jacobians: the automatic-differentiation twin (ceres::Jet),
// central differences, the error measure, and the registry of named checks that both the unit
// tests and `plucker check-jacobians` run.
//
// Error measure (docs/math.md): err(A, B) = ||A - B||_F / max(||B||_F, 1), i.e. relative for
// Jacobians of norm above one, absolute below. Thresholds: 1e-9 against autodiff, 1e-6 against
// central differences.
#pragma once

#include <ceres/jet.h>

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <ostream>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace plucker {
namespace verify {

double JacobianError(const Eigen::MatrixXd& analytic, const Eigen::MatrixXd& reference);

// Jacobian of f at x by forward-mode autodiff. F is a generic functor
//   template <typename T> Eigen::Matrix<T, kOut, 1> operator()(const Eigen::Matrix<T, kIn, 1>&)
template <int kIn, int kOut, typename F>
Eigen::Matrix<double, kOut, kIn> AutoDiffJacobian(const F& f,
                                                  const Eigen::Matrix<double, kIn, 1>& x,
                                                  Eigen::Matrix<double, kOut, 1>* value = nullptr) {
  using Jet = ceres::Jet<double, kIn>;
  Eigen::Matrix<Jet, kIn, 1> xj;
  for (int i = 0; i < kIn; ++i) xj(i) = Jet(x(i), i);
  const Eigen::Matrix<Jet, kOut, 1> yj = f(xj);
  Eigen::Matrix<double, kOut, kIn> J;
  for (int r = 0; r < kOut; ++r) {
    J.row(r) = yj(r).v.transpose();
    if (value) (*value)(r) = yj(r).a;
  }
  return J;
}

// Central differences of f at x with step h (f maps R^n -> R^m, dynamic sizes).
Eigen::MatrixXd NumericJacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                const Eigen::VectorXd& x, double h = 1e-6);

// Ridders' extrapolation of central differences (Numerical Recipes, 3rd ed., section 5.7): per
// column, differences at steps h0, h0/2, ..., h0/2^(levels-1), extrapolated to step 0 in a Neville
// tableau; the entry with the smallest error estimate is kept, and the tableau stops once its
// error grows. A fixed step trades truncation (curvature, e.g. a line 1 km away) against rounding
// (large coordinates); this reaches ~1e-10 where a fixed 1e-6 step reaches ~1e-7, and it starts
// far enough above the rounding level that a kink near x (a point on an edge) is stepped over only
// by the coarse levels it discards.
Eigen::MatrixXd RiddersJacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                const Eigen::VectorXd& x, double h0, int levels = 10);

// Statistics of one named check over many samples.
struct JacobianCheckStats {
  std::string name;
  int samples = 0;
  int skipped = 0;              // samples rejected as invalid configurations (e.g. guarded cases)
  double worst_autodiff = 0.0;  // worst err(analytic, autodiff)
  double worst_numeric = 0.0;   // worst err(analytic, central differences)
  double autodiff_tolerance = 1e-9;
  double numeric_tolerance = 1e-6;
  int failures = 0;           // samples over either tolerance
  std::string first_failure;  // description of the first failing sample
  bool passed() const { return failures == 0 && samples > 0; }

  // "autodiff 1.23e-15, numeric 4.56e-09": the worst errors, for logs and test properties.
  std::string WorstErrors() const;

  // Records one sample. `what` describes the configuration for the failure message.
  void Add(const Eigen::MatrixXd& analytic, const Eigen::MatrixXd& autodiff,
           const Eigen::MatrixXd& numeric, const std::string& what = "");
};

// One sample of a factor check as evaluated: what the factor was made from (the measurement and
// constants, named as the Python factories' arguments, python/src/factors.cc), its parameter
// blocks and the analytic residual and ambient Jacobians (evaluated false: the factor refused).
struct FactorSampleRecord {
  std::string what;
  std::vector<std::pair<std::string, Eigen::VectorXd>> inputs;
  std::vector<Eigen::VectorXd> x;
  bool evaluated = false;
  Eigen::VectorXd residual;
  std::vector<Eigen::MatrixXd> jacobians;
};

struct JacobianCheckOptions {
  int samples = 1000;
  std::uint64_t seed = 42;
  // Called with every sample a factor check evaluates (the Python bindings' test rebuilds each
  // factor from it and compares); unset: nothing.
  std::function<void(const FactorSampleRecord&)> factor_sample_observer;
};

struct NamedJacobianCheck {
  std::string name;
  std::function<JacobianCheckStats(const JacobianCheckOptions&)> run;
};
inline void PrintTo(const NamedJacobianCheck& c, std::ostream* os) { *os << c.name; }

// Each layer contributes its checks (defined next to the code they verify, in verify/).
std::vector<NamedJacobianCheck> GeometryJacobianChecks();
std::vector<NamedJacobianCheck> FactorJacobianChecks();
std::vector<NamedJacobianCheck> AllJacobianChecks();

// A selection of checks run as a test runs it. ok() only if exactly `expected_checks` names
// contain the filter and each check passed on at least options.samples samples: a misspelled
// filter or a renamed check fails instead of passing on an empty selection.
struct JacobianCheckRun {
  std::vector<JacobianCheckStats> stats;  // one per selected check, in registry order
  std::string error;                      // why the run failed; empty when ok
  bool ok() const { return error.empty(); }
};
JacobianCheckRun RunJacobianChecks(const std::vector<NamedJacobianCheck>& checks,
                                   const std::string& filter, int expected_checks,
                                   const JacobianCheckOptions& options);

}  // namespace verify
}  // namespace plucker
