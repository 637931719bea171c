// plucker check-jacobians: runs every registered Jacobian check on fresh random samples and prints
// one row per function (samples, worst error vs autodiff, vs central differences).
#include <chrono>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>

#include "commands.h"
#include "plucker/verify/jacobian_check.h"

namespace plucker {
namespace app {

namespace {

struct CheckJacobiansArgs {
  int samples = 1000;
  long long seed = -1;  // -1: fresh seed from the clock
  std::string filter;
  bool json = false;
  bool list = false;
};

int RunCheckJacobians(const CheckJacobiansArgs& args) {
  if (args.samples < 1) {
    std::cerr << "plucker check-jacobians: error: --samples must be >= 1\n";
    return 2;
  }
  verify::JacobianCheckOptions options;
  options.samples = args.samples;
  options.seed =
      args.seed >= 0
          ? static_cast<std::uint64_t>(args.seed)
          : static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
  nlohmann::json rows = nlohmann::json::array();
  int failed = 0, run = 0;
  if (!args.json && !args.list) {
    std::printf("seed %llu, %d samples per function; error = |A-B|_F / max(|B|_F, 1)\n",
                static_cast<unsigned long long>(options.seed), options.samples);
    std::printf("%-40s %8s %8s %14s %14s  %s\n", "function", "samples", "skipped", "vs autodiff",
                "vs numeric", "result");
  }
  for (const auto& check : verify::AllJacobianChecks()) {
    if (check.name.find(args.filter) == std::string::npos) continue;
    if (args.list) {
      std::cout << check.name << "\n";
      continue;
    }
    const verify::JacobianCheckStats s = check.run(options);
    ++run;
    if (!s.passed()) ++failed;
    if (args.json) {
      rows.push_back({{"function", s.name},
                      {"samples", s.samples},
                      {"skipped", s.skipped},
                      {"worst_error_vs_autodiff", s.worst_autodiff},
                      {"worst_error_vs_numeric", s.worst_numeric},
                      {"autodiff_tolerance", s.autodiff_tolerance},
                      {"numeric_tolerance", s.numeric_tolerance},
                      {"failures", s.failures},
                      {"passed", s.passed()}});
    } else {
      std::printf("%-40s %8d %8d %14.3e %14.3e  %s\n", s.name.c_str(), s.samples, s.skipped,
                  s.worst_autodiff, s.worst_numeric, s.passed() ? "ok" : "FAIL");
      if (!s.passed() && !s.first_failure.empty()) std::cerr << s.first_failure << "\n";
    }
  }
  if (args.list) return 0;
  if (args.json) {
    nlohmann::json out = {{"seed", options.seed},
                          {"samples", options.samples},
                          {"functions", rows},
                          {"failed", failed}};
    std::cout << out.dump(2) << "\n";
  } else {
    std::printf("%d functions checked, %d failed\n", run, failed);
  }
  if (run == 0) {
    std::cerr << "plucker check-jacobians: error: no check matches --filter '" << args.filter
              << "'\n";
    return 2;
  }
  return failed == 0 ? 0 : 1;
}

}  // namespace

void RegisterCheckJacobians(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<CheckJacobiansArgs>();
  CLI::App* cmd = app.add_subcommand(
      "check-jacobians",
      "Compare every analytic Jacobian with its autodiff twin and central differences");
  cmd->add_option("--samples", args->samples, "Random configurations per function")
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "Random seed (default: fresh from the clock)");
  cmd->add_option("--filter", args->filter, "Only functions whose name contains this text");
  cmd->add_flag("--json", args->json, "Machine-readable output");
  cmd->add_flag("--list", args->list, "List the checked functions and exit");
  cmd->callback([args, exit_code]() { *exit_code = RunCheckJacobians(*args); });
}

}  // namespace app
}  // namespace plucker
