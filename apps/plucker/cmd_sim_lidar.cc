// plucker sim lidar: simulate a spinning LiDAR on a vehicle driving through a procedural scene
// and write a KITTI-layout sequence (see docs/lidar-io.md):
//   DIR/velodyne/NNNNNN.bin   scans (float32 x y z intensity, ring by ring, LiDAR frame)
//   DIR/pcd/NNNNNN.pcd        with --distortion: the same scans with ring and per-point time
//   DIR/poses.txt             ground truth T_s0_si (LiDAR frame of scan 0 <- scan i), KITTI rows
//   DIR/times.txt             scan start times (s)
//   DIR/plucker_sim_lidar.txt the parameters; marks DIR as a simulator output
// No calib.txt is written: the poses are LiDAR poses, so the odometry output is compared as is.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "commands.h"
#include "plucker/io/io_error.h"
#include "plucker/io/kitti_lidar.h"
#include "plucker/io/pcd.h"
#include "plucker/io/trajectory_io.h"
#include "plucker/sensor/lidar_model.h"
#include "plucker/sim/lidar_scene.h"
#include "plucker/sim/lidar_sim.h"
#include "run_guarded.h"

namespace plucker {
namespace app {
namespace {

namespace fs = std::filesystem;

constexpr const char* kMarker = "plucker_sim_lidar.txt";

struct SimLidarArgs {
  std::string out;
  std::string scene = "urban";
  int frames = 100;
  std::string sensor = "hdl64";
  std::uint64_t seed = 1;
  double noise = 0.02;
  bool distortion = false;
  double speed_variation = 0.0;  // m/s, sinusoidal over 4 s (accelerations): VehicleTrajectory
  double speed = 0.0;            // m/s; 0: the scene's (urban, corridor 10, highway 30)
};

// Refuses a non-empty folder that is not a previous simulator output; clears the frames of a
// previous output (so that no stale frame survives a shorter run).
void PrepareOutput(const fs::path& out) {
  std::error_code ec;
  if (fs::exists(out, ec)) {
    if (!fs::is_directory(out, ec)) throw io::IoError(out.string(), "exists and is not a folder");
    const bool empty = fs::is_empty(out, ec);
    if (!empty && !fs::exists(out / kMarker, ec)) {
      throw io::IoError(out.string(),
                        "folder is not empty and is not a previous 'plucker sim lidar' output "
                        "(no " +
                            std::string(kMarker) + "); refusing to write into it");
    }
    for (const char* sub : {"velodyne", "pcd"}) {
      if (!fs::is_directory(out / sub, ec)) continue;
      for (const auto& e : fs::directory_iterator(out / sub, ec)) {
        const std::string ext = e.path().extension().string();
        if (ext == ".bin" || ext == ".pcd") fs::remove(e.path(), ec);
      }
      if (fs::is_empty(out / sub, ec)) fs::remove(out / sub, ec);
    }
  }
  fs::create_directories(out / "velodyne", ec);
  if (ec) throw io::IoError((out / "velodyne").string(), "cannot create folder: " + ec.message());
}

std::string FrameName(int i, const char* ext) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%06d%s", i, ext);
  return buf;
}

int Run(const SimLidarArgs& args) {
  if (args.frames < 1) throw std::invalid_argument("--frames must be >= 1");
  if (!(args.noise >= 0)) throw std::invalid_argument("--noise must be >= 0");
  const sensor::LidarModel sensor = sensor::LidarModelFromName(args.sensor);
  const sim::LidarScene scene = sim::MakeScene(args.scene, args.seed);
  if (!(args.speed >= 0.0 && args.speed <= 60.0))
    throw std::invalid_argument("--speed must be in (0, 60] m/s (0: the scene's default)");
  sim::VehicleTrajectoryOptions motion;
  motion.speed = args.speed > 0.0 ? args.speed : scene.route_speed;
  motion.corner_radius = scene.route_corner_radius;
  if (!(args.speed_variation >= 0.0 && args.speed_variation < motion.speed)) {
    throw std::invalid_argument("--speed-variation must be in [0, speed) m/s (the speed is " +
                                std::to_string(motion.speed) + " m/s)");
  }
  motion.speed_variation = args.speed_variation;
  const sim::VehicleTrajectory trajectory(scene.route, motion);

  const sim::LidarSimOptions options =
      sim::LidarSimOptionsFor(sensor, args.noise, args.distortion, args.seed);
  const sim::LidarSimulator simulator(scene, options);

  const fs::path out(args.out);
  PrepareOutput(out);
  if (args.distortion) {
    std::error_code ec;
    fs::create_directories(out / "pcd", ec);
    if (ec) throw io::IoError((out / "pcd").string(), "cannot create folder: " + ec.message());
  }
  std::ostringstream marker;
  marker << "# plucker sim lidar output (ground truth poses.txt = T_s0_si, LiDAR frame)\n"
         << "scene " << args.scene << "\nsensor " << sensor.name << "\nframes " << args.frames
         << "\nseed " << args.seed << "\nnoise " << args.noise << "\ndistortion "
         << (args.distortion ? 1 : 0) << "\nrate_hz " << sensor.rate_hz << "\nloop_length_m "
         << trajectory.loop_length() << "\nspeed_m_s " << motion.speed << "\n";
  if (args.speed_variation > 0.0)
    marker << "speed_variation " << args.speed_variation << " (m/s, period " << motion.speed_period
           << " s)\n";
  io::WriteFileAtomically((out / kMarker).string(), marker.str());

  std::vector<SE3d> poses;
  std::vector<double> times;
  poses.reserve(args.frames);
  times.reserve(args.frames);
  const SE3d T_s0_w = trajectory.T_w_s(0.0).Inverse();
  const auto start = std::chrono::steady_clock::now();
  std::size_t total_points = 0;
  for (int i = 0; i < args.frames; ++i) {
    const double t = i / sensor.rate_hz;
    const LidarScan scan = simulator.Scan(trajectory, t, static_cast<std::size_t>(i));
    total_points += scan.size();
    io::WriteKittiBin((out / "velodyne" / FrameName(i, ".bin")).string(), scan);
    if (args.distortion) io::WritePcd((out / "pcd" / FrameName(i, ".pcd")).string(), scan);
    poses.push_back(T_s0_w * trajectory.T_w_s(t));
    times.push_back(t);
    if ((i + 1) % 10 == 0 || i + 1 == args.frames) {
      std::cerr << "\rplucker sim lidar: frame " << (i + 1) << "/" << args.frames << std::flush;
    }
  }
  std::cerr << "\n";
  io::WriteKittiPoses((out / "poses.txt").string(), poses);
  io::WriteKittiTimes((out / "times.txt").string(), times);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("wrote %d %s frames (%s scene, %.0f points/frame, %.1f ms/frame) to %s\n",
              args.frames, sensor.name.c_str(), args.scene.c_str(),
              static_cast<double>(total_points) / args.frames, 1e3 * seconds / args.frames,
              args.out.c_str());
  return 0;
}

}  // namespace

void RegisterSimLidar(CLI::App& sim, int* exit_code) {
  auto args = std::make_shared<SimLidarArgs>();
  CLI::App* cmd = sim.add_subcommand(
      "lidar", "Simulate a spinning LiDAR on a vehicle; writes a KITTI-layout sequence");
  cmd->add_option("--out", args->out, "Output folder (new, empty or a previous sim output)")
      ->required();
  cmd->add_option("--scene", args->scene,
                  "Scene: urban (street grid, >1 km loop), corridor or highway (open road, "
                  "guard rails, sparse poles; 9 km loop, 30 m/s)")
      ->check(CLI::IsMember({"urban", "corridor", "highway"}))
      ->capture_default_str();
  cmd->add_option("--frames", args->frames, "Number of scans (10 Hz)")->capture_default_str();
  cmd->add_option("--sensor", args->sensor,
                  "Sensor model: hdl64, vlp32, vlp16, os1-64, os1-128 (spinning, rings) or "
                  "generic (Livox-like: no rings, no spinning order)")
      ->check(CLI::IsMember({"hdl64", "vlp32", "vlp16", "os1-64", "os1-128", "generic"}))
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "Random seed (scene layout and noise)")
      ->capture_default_str();
  cmd->add_option("--noise", args->noise, "Range noise sigma (m, Gaussian)")->capture_default_str();
  cmd->add_flag("--distortion", args->distortion,
                "Move the sensor during each sweep and also write pcd/NNNNNN.pcd with per-point "
                "time (for deskewing)");
  cmd->add_option("--speed", args->speed,
                  "Vehicle speed (m/s; default 0: the scene's, 10 for urban and corridor, 30 for "
                  "highway)");
  cmd->add_option("--speed-variation", args->speed_variation,
                  "Vary the speed by this much (m/s), sinusoidally over 4 s: "
                  "accelerations up to 1.57 times this in m/s^2 (default 0: constant speed)");
  cmd->callback(
      [args, exit_code]() { RunGuarded("sim lidar", exit_code, [&] { return Run(*args); }); });
}

}  // namespace app
}  // namespace plucker
