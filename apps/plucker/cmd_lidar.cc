// `plucker lidar`: LOAM-style LiDAR odometry on a recorded sequence (KITTI layout, simulator
// output or a folder of PCD files). docs/lidar-odometry.md describes the options and the results.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>
#include <set>
#include <sstream>
#include <stdexcept>

#include "commands.h"
#include "lidar_input.h"
#include "lidar_options_table.h"
#include "lidar_sequence_defaults.h"
#include "plucker/eval/statistics.h"
#include "plucker/io/lidar_sequence.h"
#include "plucker/io/ply.h"
#include "plucker/io/trajectory_io.h"
#include "plucker/lidar/odometry.h"
#include "plucker/lidar/sensor_check.h"
#include "plucker/lidar/voxel_map.h"
#include "plucker/sensor/lidar_model.h"
#include "process_setup.h"
#include "run_guarded.h"
#include "stage_clock.h"

namespace plucker {
namespace app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct LidarArgs {
  std::string data, sequence, out, config, sensor, map, tum, json, frame = "cam0";
  std::string bag, topic, stamp = "header";  // --bag input instead of --data
  bool quiet = false;
  int threads = 1;
  double map_voxel = 0.2;
};

// ---- Helpers ------------------------------------------------------------------------------
std::string Canonical(const std::string& path) {
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(fs::absolute(path), ec);
  return ec ? path : p.string();
}

// Refuses an output path that is an input (frame, calib, times, config, ground truth) or
// another output.
void CheckOutputs(const LidarArgs& a, const io::LidarSequence* seq_or_bag) {
  std::set<std::string> inputs;
  if (!seq_or_bag) inputs.insert(Canonical(a.bag));
  static const io::LidarSequence kNoFolder;  // a bag: no folder inputs
  const io::LidarSequence& seq = seq_or_bag ? *seq_or_bag : kNoFolder;
  for (std::size_t i = 0; i < seq.size(); ++i) inputs.insert(Canonical(seq.frame(i).path));
  for (const char* name : {"calib.txt", "times.txt"})
    if (seq_or_bag) inputs.insert(Canonical((fs::path(seq.root()) / name).string()));
  if (!a.config.empty()) inputs.insert(Canonical(a.config));
  std::error_code ec;
  for (const fs::path& dir_gt : {fs::path(a.data) / "poses", fs::path(seq.root()) / "poses"}) {
    if (!fs::is_directory(dir_gt, ec)) continue;
    for (const auto& e : fs::directory_iterator(dir_gt, ec)) inputs.insert(Canonical(e.path()));
  }
  if (seq_or_bag && fs::exists(fs::path(seq.root()) / "poses.txt", ec))
    inputs.insert(Canonical((fs::path(seq.root()) / "poses.txt").string()));
  std::set<std::string> outputs;
  for (const std::string* out : {&a.out, &a.map, &a.tum, &a.json}) {
    if (out->empty()) continue;
    const std::string c = Canonical(*out);
    if (inputs.count(c)) throw std::runtime_error(*out + ": refusing to overwrite an input file");
    if (!outputs.insert(c).second)
      throw std::runtime_error(*out + ": the same file is given for two outputs");
  }
}

template <typename Derived>
nlohmann::json Vec(const Eigen::MatrixBase<Derived>& v) {
  nlohmann::json j = nlohmann::json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) j.push_back(v(i));
  return j;
}

// The first readable scan against a named spinning sensor (lidar/sensor_check.h): a cloud that
// cannot come from it is an error naming the frame, before any pose is computed.
// Point times spanning more than this are not one sweep's (a unit the readers misread).
constexpr double kMaxSweepSeconds = 1.0;

void CheckSensor(const LidarInput& seq, std::size_t i, const LidarScan& scan,
                 const std::string& sensor_name) {
  const std::string where = seq.sequence() ? seq.sequence()->frame(i).path
                                           : seq.description() + ", message " + std::to_string(i);
  if (!scan.time.empty()) {
    const double span = *std::max_element(scan.time.begin(), scan.time.end());
    if (span > kMaxSweepSeconds) {
      std::ostringstream m;
      m << where << ": the point times span " << span
        << " s, more than one sweep: the time field's unit is not the readers' (float: "
           "seconds, integer: nanoseconds; docs/lidar-odometry.md, per-point time)";
      throw std::runtime_error(m.str());
    }
  }
  if (sensor_name == "auto") return;
  const lidar::SensorCheck c =
      lidar::CheckScanMatchesSensor(scan, sensor::LidarModelFromName(sensor_name));
  if (!c.ok) throw std::runtime_error(where + ": --sensor " + sensor_name + ": " + c.reason);
}

int RunLidar(const LidarArgs& a) {
  SetUpProcess(LidarPipelineSetup());
  LidarConfig config;
  config.map_voxel_size = a.map_voxel;
  if (!a.config.empty()) LoadLidarConfig(a.config, &config);
  lidar::LidarOdometryOptions options = config.odometry;
  const double map_voxel = config.map_voxel_size;
  options.num_threads = std::max(1, a.threads);
  if (!a.sensor.empty()) options.sensor = a.sensor;  // else the config's (default auto)
  if (options.sensor != "auto") sensor::LidarModelFromName(options.sensor);  // validates it
  if (a.frame != "cam0" && a.frame != "lidar")
    throw std::runtime_error("--frame must be cam0 or lidar, got '" + a.frame + "'");

  if (a.bag.empty() == a.data.empty()) throw std::runtime_error("give --data or --bag (one)");
  if (!a.bag.empty() && a.topic.empty()) throw std::runtime_error("--bag needs --topic");
  LidarInput seq = a.bag.empty() ? LidarInput(io::LidarSequence::Open(a.data, a.sequence))
                                 : LidarInput(a.bag, a.topic, a.stamp);
  CheckOutputs(a, seq.sequence());
  if (seq.sequence()) AdaptToSequence(*seq.sequence(), &options);
  bool to_cam0 = a.frame == "cam0" && seq.T_cam0_velo().has_value();
  if (!a.quiet) std::cerr << "plucker lidar: " << seq.description() << "\n";
  if (a.frame == "cam0" && !to_cam0)
    std::cerr << "plucker lidar: " << seq.missing_calib()
              << "; poses are written in the LiDAR frame\n";

  lidar::LidarOdometry odometry(options);
  lidar::VoxelMapOptions map_options{map_voxel, 1, 0.0, 1e12};
  lidar::VoxelMap map(map_options);

  // The per-frame records are streamed to the JSON file as they come (memory stays flat on
  // long sequences); the skipped list and the summary follow at the end.
  std::ofstream json_out;
  if (!a.json.empty()) {
    json_out.open(a.json);
    if (!json_out) throw std::runtime_error(a.json + ": cannot open for writing");
    json_out << "{\n\"frames\": [";
  }
  nlohmann::json skipped = nlohmann::json::array();
  std::vector<double> total_ms, cpu_ms, times;
  std::size_t degenerate_frames = 0;
  StageClock stages(options.num_threads > 1);
  const auto run_start = Clock::now();
  auto last_progress = run_start;
  const std::size_t n = seq.size();
  LidarScan scan;  // refilled in place frame after frame (no per-frame allocation)
  std::vector<Eigen::Vector3d> scan_points;
  bool sensor_checked = false;
  for (std::size_t i = 0; i < n; ++i) {
    const auto t0 = Clock::now();
    const double cpu0 = ThreadCpuMs();
    std::string error;
    double stamp = 0.0;
    const bool read_ok = seq.Read(i, &scan, &error, &stamp);
    const double read_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    const double read_cpu_ms = ThreadCpuMs() - cpu0;
    times.push_back(stamp);

    if (read_ok && !sensor_checked) {
      CheckSensor(seq, i, scan, options.sensor);
      sensor_checked = true;
    }
    lidar::FrameResult r;
    double odometry_ms = 0.0, odometry_cpu_ms = 0.0;
    if (!read_ok) {
      r = odometry.SkipFrame(error, stamp);
    } else {
      if (!a.map.empty()) scan_points = scan.points;
      const auto t1 = Clock::now();
      const double cpu1 = ThreadCpuMs();
      r = odometry.ProcessScan(std::move(scan), stages.Observer());  // in place: buffers stay
      odometry_cpu_ms = ThreadCpuMs() - cpu1;
      odometry_ms = std::chrono::duration<double, std::milli>(Clock::now() - t1).count();
    }
    if (!r.ok) skipped.push_back({{"frame", i}, {"reason", r.error}});
    if (r.ok && !a.map.empty()) {
      const Eigen::Matrix3d R = r.T_w_s.RotationMatrix();
      const Eigen::Vector3d t = r.T_w_s.translation();
      std::vector<Eigen::Vector3d> world;
      world.reserve(scan_points.size());
      const double min_sq = options.features.min_range * options.features.min_range;
      const double max_sq = options.features.max_range * options.features.max_range;
      for (const auto& p : scan_points) {
        const double sq = p.squaredNorm();
        if (sq >= min_sq && sq <= max_sq) world.push_back(R * p + t);
      }
      map.AddPoints(world);
    }
    const double frame_ms = read_ms + odometry_ms;
    const double frame_cpu_ms = read_cpu_ms + odometry_cpu_ms;
    if (read_ok) {
      total_ms.push_back(frame_ms);
      cpu_ms.push_back(frame_cpu_ms);
    }
    if (r.degeneracy.degenerate && r.ok) ++degenerate_frames;
    if (!a.json.empty()) {
      nlohmann::json ms = {{kLidarReadStageName, options.num_threads > 1 ? read_ms : read_cpu_ms},
                           {"total_cpu", frame_cpu_ms},
                           {"total_wall", frame_ms}};
      for (int s = 0; s < lidar::kNumStages; ++s)
        ms[kLidarStageNames[s]] = read_ok ? stages.ms(s) : 0.0;
      nlohmann::json f = {{"frame", i},
                          {"ok", r.ok},
                          {"ms", ms},
                          {"association_rounds", r.association_rounds},
                          {"features",  // before the caps (edge_points, plane_points: after)
                           {{"valid", r.features.valid_points},
                            {"edges", r.features.edges},
                            {"planes", r.features.planes}}},
                          {"edge_points", r.edge_points},
                          {"plane_points", r.plane_points},
                          {"edge_correspondences", r.edge_correspondences},
                          {"plane_correspondences", r.plane_correspondences},
                          {"iterations", r.solver_iterations},
                          {"degenerate", r.degeneracy.degenerate},
                          {"degenerate_directions", r.degeneracy.num_degenerate_directions},
                          {"eigenvalues", Vec(r.degeneracy.eigenvalues)},
                          {"translation_ratios", Vec(r.degeneracy.translation_ratios)},
                          {"rotation_ratios", Vec(r.degeneracy.rotation_ratios)},
                          {"translation_information", Vec(r.degeneracy.translation_information)},
                          {"rotation_information", Vec(r.degeneracy.rotation_information)},
                          {"deskewed", r.deskewed},
                          {"map_points", r.map_points}};
      if (!r.ok) f["error"] = r.error;
      json_out << (i == 0 ? "\n" : ",\n") << f.dump();
    }
    const auto now = Clock::now();
    if (!a.quiet &&
        (std::chrono::duration<double>(now - last_progress).count() > 0.5 || i + 1 == n)) {
      last_progress = now;
      const double elapsed = std::chrono::duration<double>(now - run_start).count();
      const double fps = (i + 1) / std::max(elapsed, 1e-9);
      std::cerr << "\rframe " << (i + 1) << "/" << n << "  " << std::fixed << std::setprecision(1)
                << fps << " fps  ETA " << (n - i - 1) / fps << " s   " << std::flush;
    }
  }
  if (!a.quiet) std::cerr << "\n";

  std::vector<SE3d> poses = odometry.poses();
  if (to_cam0) {
    const SE3d& Tr = *seq.T_cam0_velo();
    const SE3d Tr_inv = Tr.Inverse();
    for (SE3d& T : poses) T = Tr * T * Tr_inv;
  }
  io::WriteKittiPoses(a.out, poses);
  if (!a.tum.empty()) io::WriteTumTrajectory(a.tum, times, poses);
  if (!a.map.empty()) {
    std::vector<Eigen::Vector3d> points = map.Points();
    if (to_cam0) {
      const SE3d& Tr = *seq.T_cam0_velo();
      for (auto& p : points) p = Tr * p;
    }
    io::WritePly(a.map, points);
  }
  const double wall = std::chrono::duration<double>(Clock::now() - run_start).count();
  // One thread: CPU time of the processing thread (robust to a loaded machine). Several: wall.
  const bool threaded = options.num_threads > 1;
  const std::vector<double>& frame_ms = threaded ? total_ms : cpu_ms;
  const double median = eval::Percentile(frame_ms, 0.5), p95 = eval::Percentile(frame_ms, 0.95);
  const double median_wall = eval::Percentile(total_ms, 0.5),
               p95_wall = eval::Percentile(total_ms, 0.95);
  if (!a.json.empty()) {
    nlohmann::json summary = {
        {"frames", n},
        {"skipped", skipped.size()},
        {"degenerate_frames", degenerate_frames},
        {"median_ms", median},
        {"p95_ms", p95},
        {"mean_ms", frame_ms.empty()
                        ? 0.0
                        : std::accumulate(frame_ms.begin(), frame_ms.end(), 0.0) / frame_ms.size()},
        {"median_wall_ms", median_wall},
        {"p95_wall_ms", p95_wall},
        {"timing_note", threaded ? "several threads: per-frame ms and stages are wall-clock "
                                   "(read + odometry)"
                                 : "per-frame ms are CPU time of the processing thread (read + "
                                   "odometry); *_wall_ms are wall-clock and include waiting for "
                                   "the CPU on a loaded machine"},
        {"fps", n / std::max(wall, 1e-9)},
        {"wall_s", wall},
        {"threads", options.num_threads},
        {"output_frame", to_cam0 ? "cam0" : "lidar"}};
    json_out << "\n],\n\"skipped\": " << skipped.dump() << ",\n\"summary\": " << summary.dump(1)
             << "\n}\n";
    json_out.close();
    if (!json_out) throw std::runtime_error(a.json + ": write failed");
  }
  if (!a.quiet) {
    std::cerr << "plucker lidar: " << n << " frames (" << skipped.size() << " skipped, "
              << degenerate_frames << " degenerate), median " << std::setprecision(1) << median
              << " ms, p95 " << p95;
    if (threaded)
      std::cerr << " ms wall per frame on " << options.num_threads << " threads";
    else
      std::cerr << " ms CPU per frame (wall " << median_wall << " / " << p95_wall << " ms)";
    std::cerr << "; poses (" << (to_cam0 ? "cam0" : "lidar") << " frame) -> " << a.out << "\n";
  } else if (!skipped.empty()) {
    std::cerr << "plucker lidar: warning: " << skipped.size() << " of " << n
              << " frames skipped (poses predicted)\n";
  }
  // Skipped frames are warnings: reported with --quiet too.
  for (const auto& s : skipped)
    std::cerr << "  skipped frame " << s["frame"].get<std::size_t>() << ": "
              << s["reason"].get<std::string>() << "\n";
  if (!seq.bag_summary().empty()) std::cerr << "plucker lidar: " << seq.bag_summary() << "\n";
  return 0;
}

}  // namespace

void RegisterLidar(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<LidarArgs>();
  CLI::App* cmd = app.add_subcommand(
      "lidar", "LOAM-style LiDAR odometry (edge/plane features, scan-to-map, analytic factors)");
  cmd->add_option("--data", args->data, "Sequence folder (KITTI root, sequence folder, sim, PCD)");
  cmd->add_option("--bag", args->bag, "ROS 1 bag instead of --data (docs/bags.md)");
  cmd->add_option("--topic", args->topic, "PointCloud2 topic of --bag");
  cmd->add_option("--stamp", args->stamp,
                  "Frame times and order of --bag: header (default) | receive")
      ->check(CLI::IsMember({"header", "receive"}));
  cmd->add_option("--sequence", args->sequence, "KITTI sequence under DATA/sequences (e.g. 00)");
  cmd->add_option("--out", args->out, "Output poses, KITTI format (cam0 frame when Tr is known)")
      ->required();
  cmd->add_option("--config", args->config,
                  "YAML options (every key with its default: `plucker config lidar`, "
                  "config/lidar_default.yaml)");
  cmd->add_option("--sensor", args->sensor,
                  "auto (default: rings from the cloud's ring field or firing order) | hdl64 | "
                  "vlp32 | vlp16 | os1-64 | os1-128 (their elevation tables for clouds without "
                  "rings; the first scan must fit) | generic (no rings, no spinning order: "
                  "features from local geometry); overrides the config key `sensor`")
      ->check(CLI::IsMember({"auto", "hdl64", "vlp32", "vlp16", "os1-64", "os1-128", "generic"}));
  cmd->add_option("--map", args->map, "Write the accumulated, voxel-downsampled map (PLY)");
  cmd->add_option("--map-voxel", args->map_voxel, "Voxel size of --map in metres (default 0.2)");
  cmd->add_option("--tum", args->tum, "Also write a TUM trajectory (times from times.txt)");
  cmd->add_option("--json", args->json, "Per-frame statistics and timing summary (JSON)");
  cmd->add_option("--frame", args->frame, "Output frame: cam0 (default, needs calib Tr) | lidar")
      ->check(CLI::IsMember({"cam0", "lidar"}));
  cmd->add_flag("--quiet", args->quiet, "No progress output (skipped frames are still reported)");
  cmd->add_option("--threads", args->threads,
                  "Threads for correspondences and the solver (default 1); with more than one, "
                  "timings are wall-clock");
  cmd->callback(
      [args, exit_code]() { RunGuarded("lidar", exit_code, [&] { return RunLidar(*args); }); });
}

}  // namespace app
}  // namespace plucker
