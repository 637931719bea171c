// Measuring the factors' analytic Evaluate against their autodiff twins (shared by
// benchmarks/factors_benchmark.cc and `plucker bench factors`). No printing here.
//
// One evaluation = residual + every Jacobian (all parameter blocks), as Ceres requests them in a
// solve. Each factor is built for `kFactorBenchInputs` distinct seeded random measurements and
// parameter values, and the timing loop cycles through them, so that branch predictors and caches
// see realistic variety. Residuals and Jacobians are folded into a checksum so the work cannot be
// optimised away.
#pragma once

#include <ceres/cost_function.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace plucker {
namespace verify {

struct FactorBenchRow {
  std::string name;
  double analytic_ns = 0.0;  // thread CPU ns per evaluation (best of several rounds)
  double autodiff_ns = 0.0;
  double ratio = 0.0;           // autodiff_ns / analytic_ns (the speed-up of the analytic version)
  double flops_estimate = 0.0;  // hand count of floating-point operations of the analytic version
  double target_ratio = 2.0;    // the speed-up the analytic version should reach (3 for lines)
};

constexpr int kFactorBenchInputs = 256;

// One factor with its distinct inputs (cost functions and parameter values).
struct FactorBenchCase {
  std::string name;
  double flops_estimate = 0.0;
  double target_ratio = 2.0;  // the speed-up the analytic version is expected to reach
  std::vector<std::unique_ptr<ceres::CostFunction>> analytic, autodiff;
  std::vector<std::vector<std::vector<double>>> parameters;  // [input][block][value]
};

// Scratch space for Evaluate (residual + Jacobians), allocated once, reused by every evaluation.
class FactorBenchBuffers {
 public:
  explicit FactorBenchBuffers(const ceres::CostFunction& f);
  double* residuals() { return residuals_.data(); }
  double** jacobians() { return pointers_.data(); }
  // Sum of a residual and a Jacobian entry (fed to a sink so the evaluation stays live).
  double Checksum() const;

 private:
  std::vector<double> residuals_;
  std::vector<std::vector<double>> storage_;
  std::vector<double*> pointers_;
};

// The benchmarked factors: PointToPlane, PointToEdge, PointToEdge2, PointToEdgeScalar,
// PointReprojection, PointReprojectionVI, LineReprojection, LineReprojectionVI,
// ImuPreintegration (in that order).
std::vector<FactorBenchCase> MakeFactorBenchCases(std::uint64_t seed);

// Evaluates input `index` of the case once (analytic or autodiff). Returns false if Evaluate did.
bool EvaluateFactorBenchCase(const FactorBenchCase& c, bool analytic, int index,
                             FactorBenchBuffers* buffers);

// Times `evaluations` evaluations of each version of each factor (best of 20 rounds of
// evaluations/20, after a warm-up) and returns thread CPU ns per evaluation.
std::vector<FactorBenchRow> BenchmarkFactors(int evaluations, std::uint64_t seed);

}  // namespace verify
}  // namespace plucker
