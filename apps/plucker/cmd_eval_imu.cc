// `plucker eval imu --euroc DIR`: does the IMU noise model fit the sensor? Preintegrates the real
// IMU log over windows that start at ground-truth states and compares the prediction with the
// ground truth at the window's end (eval/imu_consistency.h).
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "plucker/eval/imu_consistency.h"
#include "plucker/io/euroc_imu.h"
#include "run_guarded.h"

namespace plucker {
namespace app {
namespace {

struct EvalImuArgs {
  std::string euroc;
  std::vector<double> windows{0.25, 1.0};
  int stride = 1;
  double noise_scale = 1.0;
  bool json = false;
};

nlohmann::json ToJson(const eval::ImuConsistencySummary& s) {
  return {{"window_s", s.window},
          {"windows", s.count},
          {"position_rmse_m", s.position_rmse},
          {"position_median_m", s.position_median},
          {"position_p95_m", s.position_p95},
          {"rotation_median_deg", s.rotation_median_deg},
          {"rotation_p95_deg", s.rotation_p95_deg},
          {"velocity_median_mps", s.velocity_median},
          {"chi2_mean_15dof", s.chi2_mean},
          {"chi2_median_15dof", s.chi2_median},
          {"chi2_preintegration_mean_9dof", s.chi2_preintegration_mean}};
}

void PrintTable(const io::EurocImuRecording& r, const sensor::ImuModel& m,
                const std::vector<eval::ImuConsistencySummary>& summaries) {
  std::printf("IMU log: %zu samples over %.1f s; ground truth: %zu states\n", r.imu.size(),
              r.imu.back().t - r.imu.front().t, r.ground_truth.size());
  std::printf(
      "noise model: gyro %.3g rad/s/sqrt(Hz), accel %.3g m/s^2/sqrt(Hz), gyro rw %.3g, accel rw "
      "%.3g\n",
      m.gyro_noise_density, m.accel_noise_density, m.gyro_bias_random_walk,
      m.accel_bias_random_walk);
  std::printf("%8s %7s %10s %10s %10s %10s %10s %10s %10s %10s\n", "window", "count", "pos med",
              "pos p95", "rot med", "rot p95", "vel med", "chi2/15", "chi2/9", "scale");
  std::printf("%8s %7s %10s %10s %10s %10s %10s %10s %10s %10s\n", "[s]", "", "[m]", "[m]", "[deg]",
              "[deg]", "[m/s]", "mean", "mean", "sqrt(/9)");
  for (const eval::ImuConsistencySummary& s : summaries) {
    std::printf("%8.2f %7d %10.4f %10.4f %10.4f %10.4f %10.4f %10.2f %10.2f %10.2f\n", s.window,
                s.count, s.position_median, s.position_p95, s.rotation_median_deg,
                s.rotation_p95_deg, s.velocity_median, s.chi2_mean, s.chi2_preintegration_mean,
                std::sqrt(s.chi2_preintegration_mean / 9.0));
  }
  std::printf(
      "chi2 means near 15 and 9 say the noise model fits; 'scale' is roughly the factor by "
      "which the noise figures would have to grow (ground-truth errors count against it too).\n");
}

void Run(const EvalImuArgs& a) {
  const io::EurocImuRecording r = io::ReadEurocImuRecording(a.euroc);
  if (r.ground_truth.empty()) {
    throw std::runtime_error(a.euroc + ": no mav0/state_groundtruth_estimate0/data.csv");
  }
  sensor::ImuModel m = r.imu_model;
  m.gyro_noise_density *= a.noise_scale;
  m.accel_noise_density *= a.noise_scale;
  m.gyro_bias_random_walk *= a.noise_scale;
  m.accel_bias_random_walk *= a.noise_scale;
  eval::ImuConsistencyOptions o;
  o.window_seconds = a.windows;
  o.stride = a.stride;
  const eval::ImuConsistencyResult result =
      eval::EvaluateImuConsistency(r.imu, r.ground_truth, m, o);
  if (a.json) {
    nlohmann::json j;
    j["imu_samples"] = r.imu.size();
    j["ground_truth_states"] = r.ground_truth.size();
    j["noise_scale"] = a.noise_scale;
    for (const auto& s : result.summaries) j["windows"].push_back(ToJson(s));
    std::cout << j.dump(2) << "\n";
  } else {
    PrintTable(r, m, result.summaries);
  }
}

}  // namespace

void AddEvalImu(CLI::App* eval_cmd, int* exit_code) {
  auto a = std::make_shared<EvalImuArgs>();
  CLI::App* cmd = eval_cmd->add_subcommand(
      "imu", "IMU noise model against a EuRoC log: preintegration errors and whitened residuals");
  cmd->add_option("--euroc", a->euroc, "EuRoC folder (with mav0/imu0 and ground truth)")
      ->required();
  cmd->add_option("--windows", a->windows, "Window lengths [s]")
      ->delimiter(',')
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--stride", a->stride, "Start a window at every n-th ground-truth state")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--noise-scale", a->noise_scale,
                  "Multiply every noise figure of sensor.yaml by this factor")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("--json", a->json, "Print machine-readable JSON instead of a table");
  cmd->callback([a, exit_code] { RunGuarded("eval imu", exit_code, [&] { Run(*a); }); });
}

}  // namespace app
}  // namespace plucker
