// plucker bench ba: one bundle adjustment problem with >= 1000 lines and 50 poses, solved from the
// same perturbed start with the analytic factors and with their autodiff twins, in one run.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "plucker/testing/synthetic_problem.h"

namespace plucker {
namespace app {

namespace {

struct BenchBaArgs {
  int frames = 50;
  int repeats = 1;
  bool json = false;
  std::uint64_t seed = 11;
};

int RunBenchBa(const BenchBaArgs& args) {
  ba::SyntheticProblemOptions options;
  options.simulation.scene.kind = sim::SceneKind::kFacades;
  options.simulation.scene.length = 300.0;
  options.simulation.scene.num_points = 1500;
  options.simulation.num_frames = args.frames;
  options.simulation.frame_rate_hz = 4.0;
  options.simulation.trajectory.speed = 10.0;
  options.simulation.obs.pixel_sigma = 0.5;
  options.simulation.simulate_imu = false;
  options.simulation.seed = args.seed;
  options.min_observations = 3;
  // Start errors of the size a triangulation front end leaves.
  options.rotation_noise_deg = 0.5;
  options.translation_noise_m = 0.05;
  options.point_noise_m = 0.05;
  options.line_endpoint_noise_m = 0.03;
  const ba::SyntheticProblem problem = ba::MakeSyntheticProblem(options);

  ba::BundleAdjustmentOptions ba_options;
  ba_options.point_sigma_px = ba_options.line_sigma_px = 0.5;
  ba_options.max_iterations = 200;
  struct Run {
    double best_seconds = 1e300;
    ba::BundleAdjustmentResult result;
    ba::ProblemAccuracy accuracy;
  } runs[2];
  for (int rep = 0; rep < args.repeats; ++rep) {
    for (int k = 0; k < 2; ++k) {  // interleaved so both see the same machine load
      ba_options.use_autodiff = (k == 1);
      ba::BundleAdjustmentData state = problem.initial;
      const ba::BundleAdjustmentResult r = ba::SolveBundleAdjustment(ba_options, &state);
      if (!r.success) {
        std::cerr << "plucker bench ba: error: solve failed: " << r.message << "\n";
        return 1;
      }
      if (r.solve_seconds < runs[k].best_seconds) {
        runs[k].best_seconds = r.solve_seconds;
        runs[k].result = r;
        runs[k].accuracy = ba::Evaluate(problem, state);
      }
    }
  }
  const double ratio = runs[1].best_seconds / runs[0].best_seconds;
  const double cost_rel_diff = std::abs(runs[0].result.final_cost - runs[1].result.final_cost) /
                               std::max(runs[1].result.final_cost, 1e-300);
  if (args.json) {
    nlohmann::json j;
    j["poses"] = problem.initial.T_w_c.size();
    j["lines"] = problem.initial.lines_w.size();
    j["points"] = problem.initial.points_w.size();
    j["line_residuals"] = runs[0].result.num_line_residuals;
    j["point_residuals"] = runs[0].result.num_point_residuals;
    for (int k = 0; k < 2; ++k) {
      const char* name = k == 0 ? "analytic" : "autodiff";
      j[name] = {{"seconds", runs[k].best_seconds},
                 {"iterations", runs[k].result.iterations},
                 {"final_cost", runs[k].result.final_cost},
                 {"rotation_rms_deg", runs[k].accuracy.poses.rotation_deg.rmse},
                 {"translation_rms_m", runs[k].accuracy.poses.translation_m.rmse}};
    }
    j["speedup"] = ratio;
    j["final_cost_relative_difference"] = cost_rel_diff;
    std::cout << j.dump(2) << "\n";
  } else {
    std::printf(
        "bundle adjustment: %zu poses, %zu lines, %zu points, %d line + %d point residuals"
        " (best of %d, one thread)\n",
        problem.initial.T_w_c.size(), problem.initial.lines_w.size(),
        problem.initial.points_w.size(), runs[0].result.num_line_residuals,
        runs[0].result.num_point_residuals, args.repeats);
    std::printf("%-10s %10s %6s %14s %12s %12s\n", "factors", "time [s]", "iter", "final cost",
                "rot [deg]", "trans [m]");
    for (int k = 0; k < 2; ++k) {
      std::printf("%-10s %10.3f %6d %14.6g %12.5f %12.5f\n", k == 0 ? "analytic" : "autodiff",
                  runs[k].best_seconds, runs[k].result.iterations, runs[k].result.final_cost,
                  runs[k].accuracy.poses.rotation_deg.rmse,
                  runs[k].accuracy.poses.translation_m.rmse);
    }
    std::printf("speed-up analytic vs autodiff: %.2fx; final costs differ by %.2e (relative)\n",
                ratio, cost_rel_diff);
  }
  if (problem.initial.lines_w.size() < 1000) {
    std::cerr << "plucker bench ba: warning: only " << problem.initial.lines_w.size()
              << " lines (target >= 1000)\n";
  }
  return cost_rel_diff < 1e-6 ? 0 : 1;
}

}  // namespace

void RegisterBenchBundleAdjustment(CLI::App& bench, int* exit_code) {
  auto args = std::make_shared<BenchBaArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "ba", "Bundle adjustment (>= 1000 lines, 50 poses): analytic vs autodiff factors");
  cmd->add_option("--frames", args->frames, "Camera poses")
      ->capture_default_str()
      ->check(CLI::Range(3, 1000));
  cmd->add_option("--repeats", args->repeats, "Solves per variant (best time kept)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  cmd->add_option("--seed", args->seed, "Random seed")->capture_default_str();
  cmd->add_flag("--json", args->json, "Machine-readable output");
  cmd->callback([args, exit_code]() { *exit_code = RunBenchBa(*args); });
}

}  // namespace app
}  // namespace plucker
