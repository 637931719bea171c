// plucker bench ...: performance benchmarks that print (never timed tests).
//   plucker bench factors [--json] [--evaluations N] [--seed S]
//     analytic Evaluate vs the autodiff twin, ns per evaluation (residual + all Jacobians), the
//     speed-up, a flop-count estimate, and the targets (>= 3x line factors, >= 2x the others).
// The exit code is 0 whether or not a target is met (timings depend on the machine); the
// PASS/MISS column reports it.
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "plucker/verify/factor_bench.h"

namespace plucker {
namespace app {

void RegisterBenchBundleAdjustment(CLI::App& bench, int* exit_code);  // cmd_bench_ba.cc
void RegisterBenchLidar(CLI::App& bench, int* exit_code);             // cmd_bench_lidar.cc

namespace {

// The flop estimate is converted to time at this assumed rate: 2 flop/ns = one scalar double
// operation per cycle at 2 GHz (no SIMD, no FMA overlap). It gives an order of magnitude for what
// the arithmetic alone costs; the rest is memory traffic, calls and branches.
constexpr double kAssumedFlopsPerNs = 2.0;

struct BenchFactorsArgs {
  int evaluations = 200000;
  long long seed = 7;
  bool json = false;
};

int RunBenchFactors(const BenchFactorsArgs& args) {
  if (args.evaluations < 10) {
    std::cerr << "plucker bench factors: error: --evaluations must be >= 10\n";
    return 2;
  }
  if (args.seed < 0) {
    std::cerr << "plucker bench factors: error: --seed must be >= 0\n";
    return 2;
  }
  const std::vector<verify::FactorBenchRow> rows =
      verify::BenchmarkFactors(args.evaluations, static_cast<std::uint64_t>(args.seed));
  int missed = 0;
  for (const auto& r : rows)
    if (!(r.ratio >= r.target_ratio)) ++missed;
  if (args.json) {
    nlohmann::json out = {{"evaluations", args.evaluations},
                          {"seed", args.seed},
                          {"distinct_inputs", verify::kFactorBenchInputs},
                          {"assumed_flops_per_ns", kAssumedFlopsPerNs},
                          {"factors", nlohmann::json::array()},
                          {"missed", missed}};
    for (const auto& r : rows) {
      out["factors"].push_back({{"factor", r.name},
                                {"analytic_ns", r.analytic_ns},
                                {"autodiff_ns", r.autodiff_ns},
                                {"speedup", r.ratio},
                                {"flops_estimate", r.flops_estimate},
                                {"flop_estimate_ns", r.flops_estimate / kAssumedFlopsPerNs},
                                {"target_speedup", r.target_ratio},
                                {"result", r.ratio >= r.target_ratio ? "PASS" : "MISS"}});
    }
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::printf(
      "%d evaluations per version (residual + all Jacobians), %d distinct inputs, seed %lld; "
      "thread CPU time, best of 20 rounds\nflop ns = flop estimate at an assumed %.0f flop/ns (1 "
      "scalar flop/cycle "
      "at 2 GHz)\n",
      args.evaluations, verify::kFactorBenchInputs, args.seed, kAssumedFlopsPerNs);
  std::printf("%-22s %12s %12s %9s %7s %9s %7s  %s\n", "factor", "analytic ns", "autodiff ns",
              "speed-up", "flops", "flop ns", "target", "result");
  for (const auto& r : rows) {
    std::printf("%-22s %12.1f %12.1f %8.2fx %7.0f %9.1f %6.1fx  %s\n", r.name.c_str(),
                r.analytic_ns, r.autodiff_ns, r.ratio, r.flops_estimate,
                r.flops_estimate / kAssumedFlopsPerNs, r.target_ratio,
                r.ratio >= r.target_ratio ? "PASS" : "MISS");
  }
  std::printf("%zu factors, %d below target\n", rows.size(), missed);
  return 0;
}

void RegisterBenchFactors(CLI::App& bench, int* exit_code) {
  auto args = std::make_shared<BenchFactorsArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "factors", "Time analytic factors against their autodiff twins (ns per evaluation)");
  cmd->add_option("--evaluations", args->evaluations, "Evaluations per factor and version")
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "Random seed of the inputs")->capture_default_str();
  cmd->add_flag("--json", args->json, "Machine-readable output");
  cmd->callback([args, exit_code]() { *exit_code = RunBenchFactors(*args); });
}

}  // namespace

void RegisterBench(CLI::App& app, int* exit_code) {
  CLI::App* bench = app.add_subcommand("bench", "Performance benchmarks (print, never fail)");
  bench->require_subcommand(1);
  RegisterBenchFactors(*bench, exit_code);
  RegisterBenchBundleAdjustment(*bench, exit_code);
  RegisterBenchLidar(*bench, exit_code);
  // `bench lines` is added by the vision module (vision_commands.cc).
}

}  // namespace app
}  // namespace plucker
