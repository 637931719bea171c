// plucker sim camera: simulate a camera + IMU moving through a procedural scene of points, line
// segments and planes, and write the sim format folder (docs/sim-format.md):
//   DIR/scene.txt DIR/rig.txt DIR/trajectory.txt DIR/body_states.txt DIR/imu.txt
//   DIR/points.txt DIR/segments.txt
// A non-empty DIR is only overwritten when it holds nothing but a previous simulation.
#include <cstdio>
#include <iostream>
#include <memory>

#include "commands.h"
#include "plucker/io/io_error.h"
#include "plucker/io/sim_format.h"
#include "plucker/sim/camera_observations.h"
#include "run_guarded.h"

namespace plucker {
namespace app {
namespace {

struct SimCameraArgs {
  std::string out;
  std::string scene = "room";
  int frames = 100;
  double frame_rate = 10.0;
  std::uint64_t seed = 1;
  double pixel_noise = 1.0;
  double outliers = 0.0;
  double imu_rate = 200.0;
  double standing_start = 0.0;
  std::string motion = "normal";
  std::string camera_model = "pinhole";
  double view_fov = sim::kDefaultViewFovDeg;
  std::string points = "full";
  double stereo = 0.0;  // baseline (m); 0: one camera
};

int Run(const SimCameraArgs& args) {
  std::string why;
  if (!io::IsSafeToWriteCameraImuSequence(args.out, &why)) {
    throw io::IoError(args.out, "refusing to write: " + why +
                                    " (use a new or empty folder, or a previous simulation)");
  }
  sim::CameraSimulationOptions options;
  options.scene.kind = sim::ParseSceneKind(args.scene);
  options.num_frames = args.frames;
  options.frame_rate_hz = args.frame_rate;
  options.seed = args.seed;
  options.obs.pixel_sigma = args.pixel_noise;
  options.obs.outlier_ratio = args.outliers;
  options.imu.model.rate_hz = args.imu_rate;
  options.trajectory.standing_start_s = args.standing_start;
  if (args.motion == "aggressive") sim::MakeAggressive(&options.trajectory);
  if (args.motion == "fast") sim::MakeFast(&options.trajectory);
  if (args.camera_model == "kb")
    options.rig = sim::FisheyeRig(args.view_fov, args.points == "view");
  if (args.stereo != 0.0) options.T_c0_c1 = sim::StereoPose(args.stereo);
  const sim::CameraSimulation sim = sim::SimulateCamera(options);
  io::WriteCameraImuSequence(args.out, sim::ToCameraImuSequence(sim));

  double path = 0.0;
  for (std::size_t i = 1; i < sim.T_w_b_gt.size(); ++i) {
    path += (sim.T_w_b_gt[i].translation() - sim.T_w_b_gt[i - 1].translation()).norm();
  }
  const sim::ObservationStats& st = sim.stats;
  std::printf("plucker sim camera: wrote %s\n", args.out.c_str());
  std::printf("  scene       %s: %zu points, %zu segments, %zu planes\n", args.scene.c_str(),
              sim.scene.points_w.size(), sim.scene.segments_w.size(), sim.scene.planes_w.size());
  std::printf("  frames      %zu at %g Hz (%.1f s, path %.1f m), image %dx%d\n",
              sim.frame_times.size(), args.frame_rate, sim.frame_times.back(), path, sim.rig.width,
              sim.rig.height);
  if (const auto& f = sim.rig.fisheye) {  // the default (pinhole) output unchanged
    std::printf(
        "  fisheye     Kannala-Brandt k1..k4 %g %g %g %g; segments%s in a %dx%d pinhole "
        "view, fx %.2f (%g deg)\n",
        f->coeffs.k1, f->coeffs.k2, f->coeffs.k3, f->coeffs.k4,
        f->points_in_view ? " and points" : "", f->view_width, f->view_height, f->view_K.fx,
        args.view_fov);
  }
  std::printf("  points      %d observations + %d outliers (%.1f per frame)\n",
              st.num_point_inliers, st.num_point_outliers,
              static_cast<double>(st.num_point_inliers + st.num_point_outliers) / args.frames);
  std::printf("  segments    %d observations + %d outliers (%.1f per frame)\n",
              st.num_segment_inliers, st.num_segment_outliers,
              static_cast<double>(st.num_segment_inliers + st.num_segment_outliers) / args.frames);
  if (sim.cam1) {  // the default output unchanged
    const sim::ObservationStats& s1 = sim.cam1_stats;
    std::printf("  stereo      cam1 %g m along cam0's +x: %d point + %d segment observations\n",
                args.stereo, s1.num_point_inliers + s1.num_point_outliers,
                s1.num_segment_inliers + s1.num_segment_outliers);
  }
  std::printf("  imu         %zu samples at %g Hz\n", sim.imu.size(), args.imu_rate);
  if (args.standing_start > 0.0 || args.motion != "normal") {  // the default output unchanged
    const sim::MotionStats m = sim::MeasureMotion(sim);
    std::printf("  motion      %s, standing %g s: up to %.2f m/s, %.2f rad/s\n",
                args.motion.c_str(), args.standing_start, m.max_speed, m.max_turn_rate);
  }
  std::printf("  noise       pixel sigma %g px, outlier ratio %g, seed %llu\n", args.pixel_noise,
              args.outliers, static_cast<unsigned long long>(args.seed));
  return 0;
}

}  // namespace

void RegisterSimCamera(CLI::App& sim, int* exit_code) {
  auto args = std::make_shared<SimCameraArgs>();
  CLI::App* cmd = sim.add_subcommand(
      "camera",
      "Simulate a camera + IMU in a scene of points, segments and planes; writes the "
      "sim format folder (docs/sim-format.md)");
  cmd->add_option("--out", args->out, "Output folder (new, empty or a previous simulation)")
      ->required();
  cmd->add_option("--scene", args->scene, "Scene: room, corridor or facades")
      ->check(CLI::IsMember({"room", "corridor", "facades"}))
      ->capture_default_str();
  cmd->add_option("--frames", args->frames, "Number of camera frames")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_option("--rate", args->frame_rate, "Camera frame rate (Hz)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "Random seed (scene, trajectory, noise)")
      ->capture_default_str();
  cmd->add_option("--pixel-noise", args->pixel_noise, "Pixel noise sigma (px, Gaussian)")
      ->check(CLI::Range(0.0, 1e3))
      ->capture_default_str();
  cmd->add_option("--outliers", args->outliers,
                  "Outlier ratio in [0, 0.9]: outliers / all observations (id -1)")
      ->check(CLI::Range(0.0, 0.9))
      ->capture_default_str();
  cmd->add_option("--imu-rate", args->imu_rate, "IMU rate (Hz)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--standing-start", args->standing_start,
                  "Seconds the body stands still at the start, then speeds up smoothly over 1 s")
      ->check(CLI::Range(0.0, 1e4))
      ->capture_default_str();
  cmd->add_option("--motion", args->motion,
                  "Motion: normal, aggressive (up to ~6.5 m/s, 1.2-2.8 rad/s) or fast (up to "
                  "~8 m/s, 2.2-4 rad/s); docs/sim-format.md")
      ->check(CLI::IsMember({"normal", "aggressive", "fast"}))
      ->capture_default_str();
  cmd->add_option("--camera-model", args->camera_model,
                  "Camera: pinhole (640x480, fx 400), or kb: a 512x512 Kannala-Brandt fisheye "
                  "(TUM-VI-like, 154 deg across; docs/sim-format.md)")
      ->check(CLI::IsMember({"pinhole", "kb"}))
      ->capture_default_str();
  cmd->add_option("--view-fov", args->view_fov,
                  "kb: field of view (deg) of the 512x512 undistorted pinhole view of the segments")
      ->check(CLI::Range(1.0, 169.0))
      ->capture_default_str();
  cmd->add_option("--points", args->points,
                  "kb: points in the full fisheye image (raw pixels) or in the segments' view")
      ->check(CLI::IsMember({"full", "view"}))
      ->capture_default_str();
  cmd->add_option("--stereo", args->stereo,
                  "A stereo rig: a second pinhole camera BASELINE_M metres along the first's +x "
                  "(e.g. 0.11, EuRoC-like), written to cam1_*.txt (docs/sim-format.md)")
      ->check(CLI::Range(0.001, 10.0));
  cmd->callback(
      [args, exit_code]() { RunGuarded("sim camera", exit_code, [&] { return Run(*args); }); });
}

}  // namespace app
}  // namespace plucker
