// Google Benchmark cases: each factor's analytic Evaluate against its autodiff twin, residual and
// all Jacobians per iteration, cycling through verify::kFactorBenchInputs distinct random inputs
// (the same cases as `plucker bench factors`, verify/factor_bench.h).
//   factors_benchmark [--benchmark_filter=Line] [--benchmark_min_time=0.2]
#include <benchmark/benchmark.h>

#include <memory>
#include <string>
#include <vector>

#include "plucker/verify/factor_bench.h"

namespace {

using plucker::verify::FactorBenchBuffers;
using plucker::verify::FactorBenchCase;

void RunCase(benchmark::State& state, const FactorBenchCase* c, bool analytic) {
  FactorBenchBuffers buffers(analytic ? *c->analytic.front() : *c->autodiff.front());
  const int n = static_cast<int>(c->parameters.size());
  int i = 0;
  for (auto _ : state) {
    const bool ok = plucker::verify::EvaluateFactorBenchCase(*c, analytic, i, &buffers);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(buffers.residuals()[0]);
    benchmark::ClobberMemory();
    i = i + 1 == n ? 0 : i + 1;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["flops_estimate"] = c->flops_estimate;
}

}  // namespace

int main(int argc, char** argv) {
  // The cases must outlive the benchmarks that point at them.
  static const std::vector<FactorBenchCase> cases = plucker::verify::MakeFactorBenchCases(7);
  for (const FactorBenchCase& c : cases) {
    benchmark::RegisterBenchmark((c.name + "/analytic").c_str(), RunCase, &c, true);
    benchmark::RegisterBenchmark((c.name + "/autodiff").c_str(), RunCase, &c, false);
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
