// plucker demo: the embedded default main job.
//   1. Camera: simulate a street of building facades, perturb poses, points and lines, run the
//      point + line bundle adjustment with the analytic factors, and report the errors against
//      ground truth before and after, and the time spent.
//   2. LiDAR (demo_lidar.cc): simulate a drive, run the odometry, evaluate and plot.
// Result files go to --out (default out/demo).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "demo_lidar.h"
#include "plucker/io/io_error.h"
#include "plucker/io/sim_format.h"
#include "plucker/io/trajectory_io.h"
#include "plucker/sim/camera_observations.h"
#include "plucker/testing/synthetic_problem.h"

namespace plucker {
namespace app {

namespace {

struct DemoArgs {
  std::string out = "out/demo";
  int frames = 40;
  std::uint64_t seed = 1;
  double pixel_noise = 0.5;
  bool skip_lidar = false;
  int lidar_frames = 300;
};

void PrintAccuracyRow(const char* stage, const ba::ProblemAccuracy& a) {
  std::printf("  %-9s %10.4f %10.4f %12.4f %10.4f %12.4f\n", stage, a.poses.rotation_deg.rmse,
              a.poses.translation_m.rmse, a.points_m.median, a.lines.direction_deg.median,
              a.lines.distance_m.median);
}

nlohmann::json AccuracyJson(const ba::ProblemAccuracy& a) {
  return {{"alignment_scale", a.scale},
          {"pose_rotation_rms_deg", a.poses.rotation_deg.rmse},
          {"pose_rotation_max_deg", a.poses.rotation_deg.max},
          {"pose_translation_rms_m", a.poses.translation_m.rmse},
          {"pose_translation_max_m", a.poses.translation_m.max},
          {"point_rms_m", a.points_m.rmse},
          {"point_median_m", a.points_m.median},
          {"line_direction_median_deg", a.lines.direction_deg.median},
          {"line_distance_median_m", a.lines.distance_m.median},
          {"line_direction_rms_deg", a.lines.direction_deg.rmse},
          {"line_distance_rms_m", a.lines.distance_m.rmse}};
}

std::string FormatStructure(const ba::BundleAdjustmentData& state) {
  std::string s = "# points: x y z (world)\n";
  char buf[256];
  for (const auto& p : state.points_w) {
    std::snprintf(buf, sizeof buf, "%.9g %.9g %.9g\n", p.x(), p.y(), p.z());
    s += buf;
  }
  return s;
}

std::string FormatLines(const ba::BundleAdjustmentData& state) {
  std::string s = "# Plücker lines (world): n_x n_y n_z d_x d_y d_z, |d| = 1\n";
  char buf[256];
  for (const auto& L : state.lines_w) {
    std::snprintf(buf, sizeof buf, "%.9g %.9g %.9g %.9g %.9g %.9g\n", L(0), L(1), L(2), L(3), L(4),
                  L(5));
    s += buf;
  }
  return s;
}

int RunCameraDemo(const DemoArgs& args, const std::filesystem::path& out) {
  ba::SyntheticProblemOptions options;
  options.simulation.scene.kind = sim::SceneKind::kFacades;
  options.simulation.num_frames = args.frames;
  options.simulation.frame_rate_hz = 5.0;
  options.simulation.trajectory.speed = 2.0;
  options.simulation.obs.pixel_sigma = args.pixel_noise;
  options.simulation.seed = args.seed;
  options.seed = args.seed + 1;
  options.rotation_noise_deg = 2.0;
  options.translation_noise_m = 0.2;
  options.point_noise_m = 0.2;
  options.line_endpoint_noise_m = 0.1;

  std::printf("== Camera: point + line bundle adjustment on a simulated street ==\n");
  const auto t0 = std::chrono::steady_clock::now();
  const ba::SyntheticProblem problem = ba::MakeSyntheticProblem(options);
  const double sim_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "  simulated %zu frames, %zu points, %zu lines, %zu point + %zu line observations "
      "(%.0f ms), pixel noise %.2f px\n",
      problem.initial.T_w_c.size(), problem.initial.points_w.size(), problem.initial.lines_w.size(),
      problem.initial.point_observations.size(), problem.initial.line_observations.size(), sim_ms,
      args.pixel_noise);

  ba::BundleAdjustmentData state = problem.initial;
  ba::BundleAdjustmentOptions ba_options;
  ba_options.point_sigma_px = ba_options.line_sigma_px = std::max(args.pixel_noise, 0.1);
  ba_options.huber_threshold = 3.0;
  const ba::BundleAdjustmentResult result = ba::SolveBundleAdjustment(ba_options, &state);
  if (!result.success) {
    std::cerr << "plucker demo: error: bundle adjustment failed: " << result.message << "\n";
    return 1;
  }
  // The solve fixes its gauge by its first poses only, so its scale drifts: compare after a
  // similarity alignment of the camera centres (the same for poses, points and lines).
  const auto sim3 = eval::AlignmentMode::kSim3;
  const ba::ProblemAccuracy before = ba::Evaluate(problem, problem.initial, sim3);
  const ba::ProblemAccuracy after = ba::Evaluate(problem, state, sim3);
  std::printf(
      "  errors against ground truth after a Sim(3) alignment of the camera centres (scale %.4f "
      "before, %.4f after); poses RMS, structure median:\n",
      before.scale, after.scale);
  std::printf("  %-9s %10s %10s %12s %10s %12s\n", "", "rot [deg]", "trans [m]", "points [m]",
              "line [deg]", "line [m]");
  PrintAccuracyRow("before", before);
  PrintAccuracyRow("after", after);
  std::printf("  solve: %d iterations, %.3f s, cost %.4g -> %.4g (%s)\n", result.iterations,
              result.solve_seconds, result.initial_cost, result.final_cost, result.message.c_str());

  const std::filesystem::path dir = out / "camera";
  std::filesystem::create_directories(dir / "simulation");
  io::WriteCameraImuSequence((dir / "simulation").string(),
                             sim::ToCameraImuSequence(problem.simulation));
  io::WriteKittiPoses((dir / "poses_gt.txt").string(), problem.T_w_c_gt);
  io::WriteKittiPoses((dir / "poses_initial.txt").string(), problem.initial.T_w_c);
  io::WriteKittiPoses((dir / "poses_ba.txt").string(), state.T_w_c);
  io::WriteFileAtomically((dir / "points_ba.txt").string(), FormatStructure(state));
  io::WriteFileAtomically((dir / "lines_ba.txt").string(), FormatLines(state));
  const nlohmann::json summary = {{"frames", problem.initial.T_w_c.size()},
                                  {"points", problem.initial.points_w.size()},
                                  {"lines", problem.initial.lines_w.size()},
                                  {"point_residuals", result.num_point_residuals},
                                  {"line_residuals", result.num_line_residuals},
                                  {"iterations", result.iterations},
                                  {"solve_seconds", result.solve_seconds},
                                  {"initial_cost", result.initial_cost},
                                  {"final_cost", result.final_cost},
                                  {"alignment", eval::AlignmentName(sim3)},
                                  {"before", AccuracyJson(before)},
                                  {"after", AccuracyJson(after)}};
  io::WriteFileAtomically((dir / "summary.json").string(), summary.dump(2) + "\n");
  std::printf(
      "  wrote %s/{poses_gt,poses_initial,poses_ba}.txt (KITTI format, T_w_c), "
      "points_ba.txt, lines_ba.txt, summary.json, simulation/\n",
      dir.string().c_str());
  return 0;
}

int RunDemo(const DemoArgs& args) {
  const std::filesystem::path out(args.out);
  std::error_code ec;
  if (std::filesystem::exists(out) && !std::filesystem::is_directory(out)) {
    std::cerr << "plucker demo: error: " << args.out << ": exists and is not a folder\n";
    return 2;
  }
  std::filesystem::create_directories(out, ec);
  if (ec) {
    std::cerr << "plucker demo: error: " << args.out << ": cannot create folder: " << ec.message()
              << "\n";
    return 2;
  }
  try {
    int rc = RunCameraDemo(args, out);
    if (rc == 0 && !args.skip_lidar) rc = RunLidarDemo(out / "lidar", args.lidar_frames, args.seed);
    return rc;
  } catch (const io::IoError& e) {
    std::cerr << "plucker demo: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace

void RegisterDemo(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<DemoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "demo", "Simulate, solve and evaluate: point+line bundle adjustment and LiDAR odometry");
  cmd->add_option("--out", args->out, "Output folder")->capture_default_str();
  cmd->add_option("--frames", args->frames, "Camera frames")
      ->capture_default_str()
      ->check(CLI::Range(3, 10000));
  cmd->add_option("--seed", args->seed, "Random seed")->capture_default_str();
  cmd->add_option("--pixel-noise", args->pixel_noise, "Pixel noise sigma")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10.0));
  cmd->add_option("--lidar-frames", args->lidar_frames, "LiDAR frames")
      ->capture_default_str()
      ->check(CLI::Range(2, 100000));
  cmd->add_flag("--no-lidar", args->skip_lidar, "Skip the LiDAR part");
  cmd->callback([args, exit_code]() { *exit_code = RunDemo(*args); });
}

}  // namespace app
}  // namespace plucker
