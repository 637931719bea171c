// The LiDAR part of `plucker demo`: simulated 64-beam drive through the urban scene, LiDAR
// odometry with the analytic edge/plane factors, evaluation against ground truth, plot.
#include "demo_lidar.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "plucker/eval/alignment.h"
#include "plucker/eval/ate.h"
#include "plucker/eval/kitti_metric.h"
#include "plucker/eval/plot.h"
#include "plucker/eval/rpe.h"
#include "plucker/eval/statistics.h"
#include "plucker/io/io_error.h"
#include "plucker/io/trajectory_io.h"
#include "plucker/lidar/odometry.h"
#include "plucker/sensor/lidar_model.h"
#include "plucker/sim/lidar_sim.h"

namespace plucker {
namespace app {

namespace {

std::string Fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

}  // namespace

int RunLidarDemo(const std::filesystem::path& dir, int frames, std::uint64_t seed) {
  std::printf("== LiDAR: odometry on a simulated 64-beam drive through a street grid ==\n");
  const sensor::LidarModel sensor = sensor::HDL64();
  const sim::LidarScene scene = sim::MakeScene("urban", seed);
  const sim::VehicleTrajectory trajectory(scene.route);
  const sim::LidarSimOptions sim_options =
      sim::LidarSimOptionsFor(sensor, /*range_noise_sigma=*/0.02, /*distortion=*/false, seed);
  const sim::LidarSimulator simulator(scene, sim_options);

  lidar::LidarOdometry odometry;
  std::vector<SE3d> poses_gt, estimate;
  std::vector<double> frame_ms, sim_ms_total;
  int degenerate = 0, failed = 0;
  const SE3d T_s0_w = trajectory.T_w_s(0.0).Inverse();
  for (int i = 0; i < frames; ++i) {
    const double t = i / sensor.rate_hz;
    const auto t0 = std::chrono::steady_clock::now();
    LidarScan scan = simulator.Scan(trajectory, t, static_cast<std::size_t>(i));
    const auto t1 = std::chrono::steady_clock::now();
    const lidar::FrameResult r = odometry.ProcessScan(std::move(scan));
    const auto t2 = std::chrono::steady_clock::now();
    sim_ms_total.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    frame_ms.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
    poses_gt.push_back(T_s0_w * trajectory.T_w_s(t));
    estimate.push_back(r.T_w_s);
    if (r.degeneracy.degenerate) ++degenerate;
    if (!r.ok) ++failed;
  }

  const eval::KittiResult kitti = eval::ComputeKittiMetric(poses_gt, estimate);
  const eval::AteResult ate = eval::ComputeAte(poses_gt, estimate);
  const eval::RpeResult rpe = eval::ComputeRpe(poses_gt, estimate);
  const double path = kitti.path_length;
  std::printf("  %d frames, %.0f m driven, %d degenerate, %d not registered\n", frames, path,
              degenerate, failed);
  if (kitti.has_segments()) {
    std::printf("  KITTI metric: translation %.3f %%, rotation %.4f deg/100 m (%d segments)\n",
                *kitti.translation_error_percent, *kitti.rotation_error_deg_per_100m,
                kitti.segment_count);
  } else {
    std::printf("  KITTI metric: no segment (path %.1f m < 100 m)\n", path);
  }
  std::printf("  ATE (se3): RMSE %.3f m, max %.3f m; RPE per frame: median %.2f cm, %.4f deg\n",
              ate.translation_m.rmse, ate.translation_m.max, rpe.translation_m.median * 100,
              rpe.rotation_deg.median);
  std::printf(
      "  odometry time per frame (one thread): median %.1f ms, p95 %.1f ms "
      "(simulation %.1f ms per frame, not included)\n",
      eval::Percentile(frame_ms, 0.5), eval::Percentile(frame_ms, 0.95),
      eval::Percentile(sim_ms_total, 0.5));

  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw io::IoError(dir.string(), "cannot create folder: " + ec.message());
  io::WriteKittiPoses((dir / "poses_gt.txt").string(), poses_gt);
  io::WriteKittiPoses((dir / "poses_estimate.txt").string(), estimate);
  eval::TrajectoryPlot plot;
  plot.title = kitti.has_segments()
                   ? "Simulated drive: KITTI translation error " +
                         Fixed(*kitti.translation_error_percent, 3) + " %, ATE " +
                         Fixed(ate.translation_m.rmse, 3) + " m"
                   : "Simulated drive: ATE " + Fixed(ate.translation_m.rmse, 3) + " m";
  plot.subtitle = "plucker demo, LiDAR frame (T_s0_si), " + std::to_string(frames) + " frames";
  plot.positions_gt = eval::Positions(poses_gt);
  plot.positions_est = eval::Positions(ate.aligned_estimate);
  plot.label_est = "estimate (se3 aligned)";
  plot.error_title = "Position error per pose (after se3 alignment)";
  plot.error_y_label = "position error [m]";
  eval::PlotSeries series;
  series.label = "ATE";
  for (std::size_t i = 0; i < ate.translation_errors.size(); ++i) {
    series.points.emplace_back(ate.distance[i], ate.translation_errors[i]);
  }
  plot.error_series.push_back(series);
  io::WriteFileAtomically((dir / "trajectory.svg").string(), eval::RenderTrajectoryPlotSvg(plot));
  nlohmann::json summary = {{"frames", frames},
                            {"path_length_m", path},
                            {"ate_rmse_m", ate.translation_m.rmse},
                            {"rpe_median_m", rpe.translation_m.median},
                            {"rpe_median_deg", rpe.rotation_deg.median},
                            {"median_ms_per_frame", eval::Percentile(frame_ms, 0.5)},
                            {"p95_ms_per_frame", eval::Percentile(frame_ms, 0.95)},
                            {"degenerate_frames", degenerate},
                            {"unregistered_frames", failed}};
  if (kitti.has_segments()) {
    summary["kitti_translation_percent"] = *kitti.translation_error_percent;
    summary["kitti_rotation_deg_per_100m"] = *kitti.rotation_error_deg_per_100m;
  }
  io::WriteFileAtomically((dir / "summary.json").string(), summary.dump(2) + "\n");
  std::printf(
      "  wrote %s/{poses_gt,poses_estimate}.txt (KITTI format, LiDAR frame), "
      "trajectory.svg, summary.json\n",
      dir.string().c_str());
  return 0;
}

}  // namespace app
}  // namespace plucker
