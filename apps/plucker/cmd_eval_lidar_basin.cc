// `plucker eval lidar-basin`: how far apart the first two scans of a LiDAR odometry run may be
// (no motion prior) and still register, and whether a restart after dropped scans converges.
//   basin:   a real scan pair (KITTI layout with reference poses) or a simulated one (ground
//            truth); the second scan's points are moved so that the true motion between the
//            scans is an imposed M (--translations along x, --yaws about z); a fresh odometry
//            registers the pair from identity; the error is |log(M^-1 T_est)|.
//   restart: the whole sequence with scans [k, k + n) dropped (--drops n, at the start k = 1
//            and in the middle); the error of the first scan after the gap against the last
//            one before it, and the largest per-pair error of the scans after the gap.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "lidar_options_table.h"
#include "lidar_sequence_defaults.h"
#include "plucker/io/lidar_sequence.h"
#include "plucker/io/trajectory_io.h"
#include "plucker/lidar/odometry.h"
#include "plucker/sensor/lidar_model.h"
#include "plucker/sim/lidar_scene.h"
#include "plucker/sim/lidar_sim.h"
#include "run_guarded.h"

namespace plucker {
namespace app {
namespace {

constexpr double kDeg = M_PI / 180.0;

struct BasinArgs {
  std::string data, sequence, gt, config;
  bool sim = false;
  std::string sensor = "hdl64";
  double sim_time = 5.0;
  double speed = 10.0;  // m/s
  int frames = 10;
  std::size_t pair = 0;
  std::vector<double> translations{0.5, 1.0, 1.5, 2.0, 2.5, 3.0};
  std::vector<double> yaws{0.0, 5.0, 10.0, 15.0};
  std::vector<int> drops{1, 2, 3, 5, 10};
  bool no_basin = false;
};

// Scans with their rings assigned (so that moving their points keeps the rings) and the
// reference poses T_s0_si in the LiDAR frame of the first scan.
struct Sequence {
  std::string name;
  std::vector<LidarScan> scans;
  std::vector<SE3d> T_s0_s;
};

Sequence LoadKitti(const BasinArgs& a, const lidar::LidarOdometryOptions& options) {
  const io::LidarSequence seq = io::LidarSequence::Open(a.data, a.sequence);
  if (!seq.T_cam0_velo())
    throw std::runtime_error(seq.root() + "/calib.txt: no Tr (needed to compare with --gt)");
  const io::Trajectory gt = io::ReadTrajectory(a.gt);
  const std::size_t n =
      std::min<std::size_t>({seq.size(), gt.poses.size(), static_cast<std::size_t>(a.frames)});
  if (n < 2) throw std::runtime_error(a.gt + ": fewer than 2 poses for the scans");
  const SE3d& Tr = *seq.T_cam0_velo();
  Sequence s{seq.description(), {}, {}};
  const SE3d T_velo0_w = (Tr.Inverse() * gt.poses[0] * Tr).Inverse();
  for (std::size_t i = 0; i < n; ++i) {
    LidarScan scan;
    std::string error;
    if (!seq.Read(i, &scan, &error)) throw std::runtime_error(error);
    if (options.ring_source == lidar::RingSource::kAuto && scan.ring.size() != scan.size())
      sensor::AssignRingsFromScanOrder(&scan);
    s.scans.push_back(std::move(scan));
    s.T_s0_s.push_back(T_velo0_w * Tr.Inverse() * gt.poses[i] * Tr);
  }
  return s;
}

Sequence Simulate(const BasinArgs& a) {
  const sensor::LidarModel model = sensor::LidarModelFromName(a.sensor);
  const sim::LidarScene scene = sim::MakeUrbanScene();
  sim::VehicleTrajectoryOptions motion;
  motion.speed = a.speed;
  const sim::VehicleTrajectory trajectory(scene.route, motion);
  const sim::LidarSimulator simulator(scene, sim::LidarSimOptionsFor(model, 0.02, false, 1));
  char name[160];
  std::snprintf(name, sizeof(name),
                "simulated urban street, %s, %.1f m/s, 2 cm range noise, from t = %.1f s",
                model.name.c_str(), a.speed, a.sim_time);
  Sequence s{name, {}, {}};
  const SE3d T_s0_w = trajectory.T_w_s(a.sim_time).Inverse();
  for (int i = 0; i < a.frames; ++i) {
    const double t = a.sim_time + i / model.rate_hz;
    s.scans.push_back(simulator.Scan(trajectory, t, static_cast<std::size_t>(i)));
    s.T_s0_s.push_back(T_s0_w * trajectory.T_w_s(t));
  }
  return s;
}

// Translation (m) and rotation (deg) of T.
std::pair<double, double> Size(const SE3d& T) {
  return {T.translation().norm(), LogSO3(T.rotation()).norm() / kDeg};
}

// The second scan of the pair with its points moved so that its pose in the first is T_a_b_new.
LidarScan Moved(const LidarScan& b, const SE3d& T_a_b, const SE3d& T_a_b_new) {
  LidarScan moved = b;
  const SE3d T_new_old = T_a_b_new.Inverse() * T_a_b;
  for (Eigen::Vector3d& p : moved.points) p = T_new_old * p;
  return moved;
}

void PrintBasin(const Sequence& s, const BasinArgs& a, const lidar::LidarOdometryOptions& o) {
  const std::size_t i = a.pair;
  if (i + 1 >= s.scans.size())
    throw std::runtime_error("--pair: no scan after scan " + std::to_string(i));
  const SE3d T_a_b = s.T_s0_s[i].Inverse() * s.T_s0_s[i + 1];
  std::printf(
      "basin: scans %zu-%zu of %s (reference motion %.2f m, %.2f deg), error of the "
      "first registration from identity, cm / deg (rounds: start + normal)\n\n",
      i, i + 1, s.name.c_str(), Size(T_a_b).first, Size(T_a_b).second);
  std::printf("| yaw \\ forward |");
  for (double t : a.translations) std::printf(" %.1f m |", t);
  std::printf("\n|---|");
  for (std::size_t k = 0; k < a.translations.size(); ++k) std::printf("---|");
  std::printf("\n");
  for (double yaw : a.yaws) {
    std::printf("| %.0f deg |", yaw);
    for (double t : a.translations) {
      const SE3d M(ExpSO3<double>(Eigen::Vector3d(0, 0, yaw * kDeg)), Eigen::Vector3d(t, 0, 0));
      lidar::LidarOdometry odometry(o);
      odometry.ProcessScan(s.scans[i]);
      const lidar::FrameResult r = odometry.ProcessScan(Moved(s.scans[i + 1], T_a_b, M));
      const auto [dt, dr] = Size(M.Inverse() * r.T_w_s);
      std::printf(" %.1f / %.2f (%d+%d)%s |", 100.0 * dt, dr, r.start_rounds, r.association_rounds,
                  r.ok ? "" : " failed");
    }
    std::printf("\n");
  }
}

// The per-pair errors of a run of the sequence without scans [k, k + n): skipped (SkipFrame, as
// a numbered file that is missing or unreadable) or absent (never given: only the scan times
// show the gap). Returns the error across the gap (cm, deg) and the worst pair after it (cm).
struct RestartError {
  double across_cm = 0.0, across_deg = 0.0, worst_after_cm = 0.0;
};

RestartError RunRestart(const Sequence& s, std::size_t k, std::size_t after, bool absent,
                        const lidar::LidarOdometryOptions& o) {
  lidar::LidarOdometry odometry(o);
  std::vector<std::size_t> scan_of_pose;
  for (std::size_t j = 0; j < s.scans.size(); ++j) {
    const bool dropped = j >= k && j < after;
    if (dropped && absent) continue;
    if (dropped)
      odometry.SkipFrame("dropped", s.scans[j].timestamp);
    else
      odometry.ProcessScan(s.scans[j]);
    scan_of_pose.push_back(j);
  }
  std::vector<SE3d> T(s.scans.size());
  for (std::size_t p = 0; p < scan_of_pose.size(); ++p) T[scan_of_pose[p]] = odometry.poses()[p];
  auto pair_error = [&](std::size_t x, std::size_t y) {
    const SE3d ref = s.T_s0_s[x].Inverse() * s.T_s0_s[y];
    return Size(ref.Inverse() * (T[x].Inverse() * T[y]));
  };
  RestartError e;
  const auto [gt, gr] = pair_error(k - 1, after);
  e.across_cm = 100.0 * gt, e.across_deg = gr;
  for (std::size_t j = after; j + 1 < s.scans.size(); ++j)
    e.worst_after_cm = std::max(e.worst_after_cm, 100.0 * pair_error(j, j + 1).first);
  return e;
}

// Runs the sequence without scans [k, k + n) and reports the first pair across the gap, with the
// restart handling (restart_from_stamps, restart_min_plane_match) off ("before") and as given.
void PrintRestart(const Sequence& s, const BasinArgs& a, const lidar::LidarOdometryOptions& o) {
  std::printf(
      "\nrestart: %s, scans [k, k + n) dropped: skipped (as a missing or unreadable numbered "
      "file) or absent (never given; only the scan times show the gap); error across the gap "
      "(cm / deg) and the worst pair after it (cm), without the restart handling "
      "(registration.restart_from_stamps false, restart_min_plane_match 0) and with it\n\n",
      s.name.c_str());
  std::printf(
      "| drop | k | n | gap (m) | across, before | across, now | worst after, before | worst "
      "after, now |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  lidar::LidarOdometryOptions before = o;
  before.restart_from_stamps = false;
  before.restart_min_plane_match = 0.0;
  const std::size_t mid = s.scans.size() / 2;
  for (bool absent : {false, true}) {
    for (std::size_t k : {std::size_t{1}, mid}) {
      for (int n : a.drops) {
        const std::size_t after = k + static_cast<std::size_t>(n);
        if (after + 1 >= s.scans.size()) continue;
        const RestartError b = RunRestart(s, k, after, absent, before);
        const RestartError e = RunRestart(s, k, after, absent, o);
        std::printf("| %s | %zu | %d | %.2f | %.1f / %.2f | %.1f / %.2f | %.1f | %.1f |\n",
                    absent ? "absent" : "skipped", k, n,
                    Size(s.T_s0_s[k - 1].Inverse() * s.T_s0_s[after]).first, b.across_cm,
                    b.across_deg, e.across_cm, e.across_deg, b.worst_after_cm, e.worst_after_cm);
        std::fflush(stdout);
      }
    }
  }
}

int RunBasin(const BasinArgs& a) {
  LidarConfig config;
  if (!a.config.empty()) LoadLidarConfig(a.config, &config);
  lidar::LidarOdometryOptions options = config.odometry;
  if (a.sim == !a.data.empty()) throw std::runtime_error("give either --data (with --gt) or --sim");
  if (!a.sim && a.gt.empty()) throw std::runtime_error("--data needs --gt (reference poses)");
  if (a.frames < 2) throw std::runtime_error("--frames must be >= 2");
  if (!(a.speed > 0.0 && a.speed <= 60.0))
    throw std::runtime_error("--speed must be in (0, 60] m/s");
  const Sequence s = a.sim ? Simulate(a) : LoadKitti(a, options);
  std::printf("registration.start_distance = %.2f m\n", options.start_distance);
  if (!a.no_basin) PrintBasin(s, a, options);
  PrintRestart(s, a, options);
  return 0;
}

}  // namespace

void RegisterEvalLidarBasin(CLI::App& eval, int* exit_code) {
  auto args = std::make_shared<BasinArgs>();
  CLI::App* cmd = eval.add_subcommand(
      "lidar-basin",
      "First LiDAR registration without a motion prior: error against imposed offsets, and the "
      "restart after dropped scans");
  cmd->add_option("--data", args->data, "KITTI-layout folder (with calib.txt Tr)");
  cmd->add_option("--sequence", args->sequence, "KITTI sequence under DIR/sequences/");
  cmd->add_option("--gt", args->gt, "Reference poses (KITTI cam0 format) of --data");
  cmd->add_flag("--sim", args->sim, "Simulated urban street instead (ground truth)");
  cmd->add_option("--sensor", args->sensor, "Simulated sensor (hdl64 | vlp32 | vlp16)")
      ->capture_default_str();
  cmd->add_option("--sim-time", args->sim_time, "Simulated drive: time of the first scan [s]")
      ->capture_default_str();
  cmd->add_option("--speed", args->speed, "Simulated drive: speed [m/s] (--sim)")
      ->capture_default_str();
  cmd->add_flag("--no-basin", args->no_basin, "Only the restart table");
  cmd->add_option("--frames", args->frames, "Scans used (restart runs)")->capture_default_str();
  cmd->add_option("--pair", args->pair, "Basin pair: scans i and i + 1")->capture_default_str();
  cmd->add_option("--translations", args->translations, "Imposed forward motions [m]")
      ->capture_default_str();
  cmd->add_option("--yaws", args->yaws, "Imposed yaws [deg]")->capture_default_str();
  cmd->add_option("--drops", args->drops, "Numbers of dropped scans (restart)")
      ->capture_default_str();
  cmd->add_option("--config", args->config, "plucker lidar YAML options");
  cmd->callback([args, exit_code] {
    RunGuarded("eval lidar-basin", exit_code, [&] { return RunBasin(*args); });
  });
}

}  // namespace app
}  // namespace plucker
