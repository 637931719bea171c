// plucker vio: monocular point + line visual-inertial odometry (docs/vio.md) on a features
// folder (docs/sim-format.md: rig.txt, imu.txt, points.txt, segments.txt) or a EuRoC folder (cam0
// images, imu0): a reader, the loop of a driver over the inputs in time order into
// odometry::VisualInertialOdometry (IMU samples up to each frame's time, then the frame: one
// image in memory at a time), and the writers. --out: the refined trajectory (the frames before
// the start backfilled); --out-online: the poses as returned frame by frame.
#include <CLI/CLI.hpp>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>

#include "commands.h"
#include "plucker/io/image_folder.h"
#include "plucker/io/io_error.h"
#include "plucker/odometry/visual_inertial_odometry.h"
#include "progress.h"
#include "run_guarded.h"
#include "stage_clock.h"
#include "vio_config.h"
#include "vio_input.h"
#include "vio_output.h"

namespace plucker {
namespace app {
namespace {

struct VioArgs {
  std::string features, euroc, out, out_online, json, plot, config;
  bool no_lines = false, quiet = false, estimate_extrinsic = false, estimate_time_offset = false;
  int point_stride = 1, window = 10;
  VioConfig cfg;
};

const char* kFrontendStages[vision::kNumFrontendStages] = {"points", "detection", "lines"};

// One frame through the odometry, timed; EuRoC: the image read here (unreadable: skipped).
bool Feed(const VioInput& in, std::size_t i, odometry::VisualInertialOdometry* vio,
          VioReport* report, std::vector<odometry::VioFrameRecord>* online,
          std::vector<std::string>* warnings, FrameProgress* progress) {
  BasicStageClock<window::WindowStage, window::kNumWindowStages> window_ms;
  BasicStageClock<vision::FrontendStage, vision::kNumFrontendStages> frontend_ms;
  odometry::VioFrameResult r;
  const double t0 = ThreadCpuMs();
  double frontend_total = 0.0;
  if (in.images.empty()) {
    r = vio->AddFrame(in.frames[i], window_ms.Observer());
  } else {
    const io::EurocFrame& frame = in.images[i];
    try {  // unreadable, or of another size than the calibration
      const cv::Mat image = io::ReadGrayImage(frame.image);
      const std::string blank = io::BlankImageProblem(image);  // nothing to track: skipped
      if (!blank.empty()) throw io::IoError(frame.image, blank);
      frontend_total = ThreadCpuMs() - t0;  // reading the image counts to the front end
      r = vio->AddImage(frame.t, image, frontend_ms.Observer(), window_ms.Observer());
    } catch (const std::exception& e) {
      const bool named = dynamic_cast<const io::IoError*>(&e) != nullptr;  // names the file
      warnings->push_back("skipped " + (named ? "" : frame.image + ": ") + e.what());
      ++report->skipped_images;
      progress->Break();
      std::cerr << "plucker vio: warning: " << warnings->back() << "\n";
      return false;
    }
    nlohmann::json info = {{"image", frame.image},
                           {"observed_points", r.observed_points},
                           {"observed_segments", r.observed_segments}};
    for (int k = 0; k < vision::kNumFrontendStages; ++k) {
      info["ms"][kFrontendStages[k]] = frontend_ms.ms(k);
      frontend_total += frontend_ms.ms(k);
    }
    report->AddFrontend(r.frame, info);
  }
  std::array<double, window::kNumWindowStages> stages{};
  for (int s = 0; s < window::kNumWindowStages; ++s) stages[s] = window_ms.ms(s);
  report->Add(r, stages, ThreadCpuMs() - t0, frontend_total);
  if (r.status == odometry::VioStatus::kFailed) throw io::IoError(in.source, r.message);
  odometry::VioFrameRecord pose;  // the online pose of the frame (none before the start)
  pose.frame = r.frame;
  pose.time = r.time;
  pose.T_w_b = r.T_w_b;
  online->push_back(pose);
  return true;
}

void PrintSummary(const VioArgs& a, const VioReport& report,
                  const odometry::VisualInertialOdometry& vio, const VioInput& in,
                  double duration) {
  const odometry::VioInitialization& init = vio.initialization();
  const double cpu = report.cpu_ms;
  std::cerr << "plucker vio: " << report.frames << " frames, " << init.method
            << " initialisation on frames " << init.first << "-" << init.second << ", "
            << report.keyframes << " keyframes, " << report.imu_only << " IMU-only, "
            << report.skipped + report.skipped_images << " skipped; " << std::fixed
            << std::setprecision(2) << cpu / 1e3 << " s CPU for " << duration << " s of data ("
            << (cpu > 0 ? 1e3 * duration / cpu : 0.0) << "x real time); wrote " << a.out << "\n";
  if (!a.cfg.odometry.estimate_extrinsic) return;
  const SE3d T = vio.ExtrinsicEstimate();
  const SE3d& given = in.calibration.T_b_c;
  std::cerr << "plucker vio: extrinsic " << (vio.ExtrinsicFree() ? "estimated" : "held")
            << ": T_b_c moved " << std::setprecision(3)
            << LogSO3<double>(given.rotation().conjugate() * T.rotation()).norm() * 180.0 / M_PI
            << " deg, " << std::setprecision(4) << (T.translation() - given.translation()).norm()
            << " m from the given one\n";
}

int Run(const VioArgs& a) {
  const double t_start = WallMs();
  VioConfig cfg = a.cfg;
  if (a.no_lines) cfg.odometry.use_lines = false;
  VioInput in =
      a.euroc.empty() ? ReadVioFeatures(a.features, cfg.point_stride) : ReadVioEuroc(a.euroc);
  const std::size_t n = in.images.empty() ? in.frames.size() : in.images.size();
  if (n < 3) throw io::IoError(in.source, "needs at least 3 frames, has " + std::to_string(n));
  for (const std::string& w : in.warnings) std::cerr << "plucker vio: warning: " << w << "\n";
  if (!cfg.T_b_c.empty()) {  // --config T_b_c: the extrinsic given instead of the input's
    const std::vector<double>& e = cfg.T_b_c;
    in.calibration.T_b_c =
        SE3d(Eigen::Quaterniond(e[6], e[3], e[4], e[5]), Eigen::Vector3d(e[0], e[1], e[2]));
  }
  const double read_ms = WallMs() - t_start;
  odometry::VisualInertialOdometry vio(cfg.odometry, in.calibration);
  VioReport report;
  report.extrinsic_estimated = cfg.odometry.estimate_extrinsic;
  std::vector<odometry::VioFrameRecord> online;
  std::size_t next_imu = 0;
  FrameProgress progress("plucker vio", n, a.quiet);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = in.images.empty() ? in.frames[i].time : in.images[i].t;
    // A driver delivers the IMU up to the image's timestamp before the image.
    while (next_imu < in.imu.size() && (next_imu == 0 || in.imu[next_imu - 1].t < t))
      vio.AddImu(in.imu[next_imu++]);
    if (!Feed(in, i, &vio, &report, &online, &in.warnings, &progress)) continue;
    if (progress.Due(i)) {
      progress.Show(i, "keyframes " + std::to_string(report.keyframes) + "  points " +
                           std::to_string(report.window_points) + "  lines " +
                           std::to_string(report.window_lines));
    }
  }
  progress.Break();
  while (next_imu < in.imu.size()) vio.AddImu(in.imu[next_imu++]);
  const double t_finish = ThreadCpuMs();
  const odometry::VioFrameResult end = vio.Finish();
  report.Add(end, {}, ThreadCpuMs() - t_finish);
  --report.frames;  // Finish is no frame
  if (end.status == odometry::VioStatus::kFailed) throw io::IoError(in.source, end.message);
  if (report.frames < 3) {
    throw io::IoError(in.source, "needs at least 3 frames, has " + std::to_string(report.frames));
  }
  const std::vector<odometry::VioFrameRecord>& refined = vio.RefinedTrajectory();
  WriteVioTrajectory(a.out, refined, false, in.clock_origin_ns);
  if (!a.out_online.empty()) WriteVioTrajectory(a.out_online, online, true, in.clock_origin_ns);
  if (!a.plot.empty()) WriteVioPlot(a.plot, in, refined);
  const double duration = refined.back().time - refined.front().time;
  if (!a.json.empty()) {
    nlohmann::json out = report.Json(in, vio, read_ms, WallMs() - t_start);
    out["summary"]["use_lines"] = cfg.odometry.use_lines;
    out["summary"]["point_stride"] = cfg.point_stride;
    out["summary"]["max_imu_only_share"] = cfg.max_imu_only_share;
    io::WriteFileAtomically(a.json, out.dump(1) + "\n");
  }
  if (!a.quiet) PrintSummary(a, report, vio, in, duration);
  if (report.skipped > 0) {
    std::cerr << "plucker vio: warning: " << report.skipped
              << " frames skipped (no IMU coverage or no finite pose; listed in the JSON)\n";
  }
  return WarnImuOnly(vio.statistics(), cfg.max_imu_only_share);
}

}  // namespace

void RegisterVio(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<VioArgs>();
  CLI::App* cmd = app.add_subcommand(
      "vio",
      "Monocular point + line visual-inertial odometry (docs/vio.md) on a features folder "
      "(docs/sim-format.md) or a EuRoC folder");
  CLI::Option* features = cmd->add_option(
      "--features", args->features,
      "Features folder: rig.txt, imu.txt, points.txt, segments.txt (docs/sim-format.md)");
  CLI::Option* euroc =
      cmd->add_option("--euroc", args->euroc, "EuRoC folder (mav0/cam0 images, mav0/imu0)");
  features->excludes(euroc);
  cmd->add_option("--out", args->out,
                  "Output TUM trajectory of the body frame T_w_b, refined: the frames before "
                  "the start backfilled")
      ->required();
  cmd->add_option("--out-online", args->out_online,
                  "TUM trajectory of the poses as returned frame by frame (online)");
  cmd->add_option("--json", args->json, "Per-frame statistics, stage times and a summary (JSON)");
  cmd->add_option("--plot", args->plot, "SVG: top view (against the ground truth if present)");
  cmd->add_option("--config", args->config,
                  "YAML options (docs/vio.md): any of " + VioConfigKeys() +
                      " (T_b_c: [tx, ty, tz, qx, qy, qz, qw], instead of the input's)")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--no-lines", args->no_lines, "Points only");
  CLI::Option* estimate_extrinsic =
      cmd->add_flag("--estimate-extrinsic", args->estimate_extrinsic,
                    "Estimate the camera-body extrinsic T_b_c online (docs/vio.md)");
  CLI::Option* estimate_td = cmd->add_flag(
      "--estimate-time-offset", args->estimate_time_offset,
      "Estimate the camera-IMU time offset online (t_imu = t_cam + td; JSON summary "
      "camera_imu_time_offset_s; config keys time_offset_s, time_offset_prior_sigma_s)");
  CLI::Option* stride =
      cmd->add_option("--point-stride", args->point_stride,
                      "Use the point tracks whose id is a multiple of this (features folders)")
          ->check(CLI::Range(1, 1000000))
          ->capture_default_str();
  CLI::Option* window = cmd->add_option("--window", args->window, "Keyframes in the window")
                            ->check(CLI::Range(2, 1000))
                            ->capture_default_str();
  cmd->add_flag("--quiet", args->quiet, "No progress output (warnings are still printed)");
  cmd->callback([args, exit_code, stride, window, estimate_extrinsic, estimate_td]() {
    RunGuarded("vio", exit_code, [&] {
      if (args->features.empty() == args->euroc.empty()) {
        throw std::invalid_argument("give --features DIR or --euroc DIR");
      }
      // The configuration file, then what the command line gives explicitly.
      if (!args->config.empty()) ApplyVioConfig(args->config, &args->cfg);
      if (stride->count() > 0) args->cfg.point_stride = args->point_stride;
      if (window->count() > 0) args->cfg.odometry.window = args->window;
      if (estimate_extrinsic->count() > 0) args->cfg.odometry.estimate_extrinsic = true;
      if (estimate_td->count() > 0) args->cfg.odometry.estimate_time_offset = true;
      return Run(*args);
    });
  });
}

}  // namespace app
}  // namespace plucker
