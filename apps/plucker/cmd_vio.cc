// plucker vio: monocular point + line visual-inertial odometry (docs/vio.md) on a features
// folder (docs/sim-format.md: rig.txt, imu.txt, points.txt, segments.txt), a EuRoC folder (cam0
// images, imu0) or a ROS 1 bag (image and IMU topics): a reader, the loop of a driver over the
// inputs in time order into odometry::VisualInertialOdometry (vio_stream.h: IMU samples up to
// each frame's time, then the frame: one image in memory at a time), and the writers. --out: the
// refined trajectory (the frames before the start backfilled); --out-online: the poses as returned
// frame by frame.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <opencv2/core/utility.hpp>

#include "commands.h"
#include "option_flags.h"
#include "pipeline_json.h"
#include "plucker/io/image_folder.h"
#include "plucker/io/io_error.h"
#include "plucker/odometry/visual_inertial_odometry.h"
#include "process_setup.h"
#include "progress.h"
#include "run_guarded.h"
#include "stage_clock.h"
#include "vio_checks.h"
#include "vio_config.h"
#include "vio_draw.h"
#include "vio_input.h"
#include "vio_output.h"
#include "vio_stream.h"
#include "vio_tracks.h"

namespace plucker {
namespace app {
namespace {

struct VioArgs {
  std::string features, euroc, out, out_online, json, plot, draw, tracks, config;
  VioBagSource bag;
  CameraFlags camera;
  bool no_lines = false, quiet = false, estimate_extrinsic = false, estimate_time_offset = false;
  int point_stride = 1, window = 10;
  VioConfig cfg;
};

// One frame through the odometry, timed; EuRoC: the image read here (unreadable: skipped).
bool Feed(const VioInput& in, const VioItem& item, odometry::VisualInertialOdometry* vio,
          VioReport* report, std::vector<odometry::VioFrameRecord>* online,
          std::vector<std::string>* warnings, FrameProgress* progress, VioOverlayWriter* draw) {
  BasicStageClock<window::WindowStage, window::kNumWindowStages> window_ms;
  BasicStageClock<vision::FrontendStage, vision::kNumFrontendStages> frontend_ms;
  odometry::VioFrameResult r;
  const double t0 = ThreadCpuMs();
  double frontend_total = 0.0;
  if (item.name.empty()) {
    r = vio->AddFrame(in.frames[item.frame], window_ms.Observer());
  } else {
    try {  // unreadable, or of another size than the calibration
      if (!item.problem.empty()) throw std::runtime_error(item.problem);
      const cv::Mat image = item.image.empty() ? io::ReadGrayImage(item.name) : item.image;
      const std::string blank = io::BlankImageProblem(image);  // nothing to track: skipped
      if (!blank.empty()) throw io::IoError(item.name, blank);
      frontend_total = ThreadCpuMs() - t0;  // reading the image counts to the front end
      if (draw) draw->Hold(image.clone());
      r = vio->AddImage(item.t, image, frontend_ms.Observer(), window_ms.Observer());
      if (draw) draw->Release(r);
    } catch (const std::exception& e) {
      if (draw) draw->Refused();
      const bool named = dynamic_cast<const io::IoError*>(&e) != nullptr;  // names the file
      warnings->push_back("skipped " + (named ? "" : item.name + ": ") + e.what());
      ++report->skipped_images;
      progress->Break();
      std::cerr << "plucker vio: warning: " << warnings->back() << "\n";
      return false;
    }
    nlohmann::json info = {{"image", item.name},
                           {"observed_points", r.observed_points},
                           {"observed_segments", r.observed_segments}};
    info["ms"]["read"] = frontend_total;  // the image file (decoded in the stream for a bag)
    for (int k = 0; k < vision::kNumFrontendStages; ++k) {
      info["ms"][kFrontendStageNames[k]] = frontend_ms.ms(k);
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
  pose.window = r.window;  // the online state (biases) for --plot
  online->push_back(pose);
  return true;
}

int Run(const VioArgs& a) {
  SetUpProcess(ImagePipelineSetup(), cv::setNumThreads);  // as `plucker vo`
  const double t_start = WallMs();
  const VioConfig& cfg = a.cfg;
  std::vector<std::string> inputs = CameraFlagFiles(a.camera);
  inputs.insert(inputs.end(), {a.bag.bag, a.config});
  RefuseOverwritingInputs(inputs, {a.out, a.out_online, a.json, a.plot, a.draw, a.tracks});
  VioInput in;
  const std::unique_ptr<VioStream> stream =
      OpenVioInput(a.features, a.euroc, a.bag, a.camera, cfg.point_stride, &in);
  const std::size_t n = stream->frames();
  if (n < 3) throw io::IoError(in.source, "needs at least 3 frames, has " + std::to_string(n));
  for (const std::string& w : in.warnings) std::cerr << "plucker vio: warning: " << w << "\n";
  UseConfigExtrinsic(cfg, &in.calibration.T_b_c);  // extrinsic.T_b_c instead of the input's
  const double read_ms = WallMs() - t_start;
  odometry::VisualInertialOdometry vio(cfg.odometry, in.calibration);
  std::unique_ptr<VioOverlayWriter> draw;
  if (!a.draw.empty()) draw = std::make_unique<VioOverlayWriter>(a.draw, &vio);
  std::unique_ptr<VioTrackWriter> tracks;
  if (!a.tracks.empty()) tracks = std::make_unique<VioTrackWriter>(&vio);
  VioReport report;
  report.extrinsic_estimated = cfg.odometry.estimate_extrinsic;
  std::vector<odometry::VioFrameRecord> online;
  FrameProgress progress("plucker vio", n, a.quiet);
  std::size_t i = 0;
  for (VioItem item; stream->Next(&item);) {
    if (item.is_imu) {
      vio.AddImu(item.imu);
      continue;
    }
    if (Feed(in, item, &vio, &report, &online, &in.warnings, &progress, draw.get()) &&
        progress.Due(i)) {
      progress.Show(i, "keyframes " + std::to_string(report.keyframes) + "  points " +
                           std::to_string(report.window_points) + "  lines " +
                           std::to_string(report.window_lines));
    }
    ++i;
  }
  progress.Break();
  for (const std::string& w : stream->warnings()) in.warnings.push_back(w);
  for (const std::string& w : stream->warnings())
    std::cerr << "plucker vio: warning: " << w << "\n";
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
  if (!a.plot.empty()) WriteVioPlot(a.plot, in, refined, online);
  if (tracks) tracks->Write(a.tracks, in.clock_origin_ns);
  const double duration = refined.back().time - refined.front().time;
  const std::vector<VioReport::KeyframeChi2> inconsistent =
      InconsistentKeyframes(report, cfg.max_keyframe_imu_chi2);
  const VioStartBounds start_bounds{cfg.max_start_imu_chi2, cfg.max_start_culled_share};
  const VioStartCheck start = CheckStart(report, start_bounds);
  if (!a.json.empty()) {
    nlohmann::json out = report.Json(in, vio, read_ms, WallMs() - t_start);
    out["summary"]["use_lines"] = cfg.odometry.use_lines;
    out["summary"]["point_stride"] = cfg.point_stride;
    out["summary"]["max_imu_only_share"] = cfg.max_imu_only_share;
    out["summary"]["max_keyframe_imu_chi2"] = cfg.max_keyframe_imu_chi2;
    nlohmann::json frames = nlohmann::json::array();
    for (const VioReport::KeyframeChi2& k : inconsistent) frames.push_back(k.frame);
    out["summary"]["inconsistent_keyframes"] = inconsistent.size();
    double largest = 0.0;
    for (const VioReport::KeyframeChi2& k : report.keyframe_chi2)
      largest = std::max(largest, k.chi2);
    out["summary"]["largest_keyframe_imu_chi2"] = largest;
    out["summary"]["inconsistent_keyframe_frames"] = frames;
    out["summary"]["start_check"] = StartCheckJson(start, start_bounds);
    out["summary"]["keyframe_imu_chi2"] = KeyframeChi2StatsJson(report);
    io::WriteFileAtomically(a.json, out.dump(1) + "\n");
  }
  if (!a.quiet) PrintVioSummary(a.out, cfg.odometry.estimate_extrinsic, report, vio, in, duration);
  if (report.skipped > 0) {
    std::cerr << "plucker vio: warning: " << report.skipped
              << " frames skipped (no IMU coverage or no finite pose; listed in the JSON)\n";
  }
  const int imu_only_exit = WarnImuOnly(vio.statistics(), cfg.max_imu_only_share);
  const int inconsistent_exit = WarnInconsistent(inconsistent, cfg.max_keyframe_imu_chi2);
  const int start_exit = WarnStart(start, start_bounds);
  return std::max({imu_only_exit, inconsistent_exit, start_exit});
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
  CLI::Option* bag = AddBagFlags(cmd, &args->bag, true,
                                 "ROS 1 bag (--image-topic, --imu-topic; the calibration from "
                                 "--sensor/--calib and --imu-sensor/--imu-calib)");
  features->excludes(euroc);
  bag->excludes(features)->excludes(euroc);
  AddCameraFlags(cmd, &args->camera, CameraFlagSet{false, true});
  cmd->add_option("--out", args->out,
                  "Output TUM trajectory of the body frame T_w_b, refined: the frames before "
                  "the start backfilled")
      ->required();
  cmd->add_option("--out-online", args->out_online,
                  "TUM trajectory of the poses as returned frame by frame (online)");
  cmd->add_option("--json", args->json, "Per-frame statistics, stage times and a summary (JSON)");
  cmd->add_option("--plot", args->plot,
                  "SVG: top view, position error, height and IMU biases over time (against the "
                  "ground truth if present)");
  cmd->add_option("--draw", args->draw,
                  "Folder: one PNG per frame with a pose, tracked points and line segments over "
                  "the undistorted image (the palette of `plucker vo --draw`; --euroc or --bag)");
  cmd->add_option("--tracks", args->tracks,
                  "Folder: the window's input tracks of every frame with a pose, undistorted "
                  "(points.txt, segments.txt as the simulator's rows, window_lines.txt, "
                  "frames.txt; not with --draw)");
  cmd->add_option("--config", args->config,
                  "YAML options (`plucker config vio` prints them all with their ranges; "
                  "docs/vio.md); a flag given on the command line overrides its key")
      ->check(CLI::ExistingFile);
  CLI::Option* no_lines = cmd->add_flag("--no-lines", args->no_lines, "Points only (use_lines)");
  CLI::Option* estimate_extrinsic =
      cmd->add_flag("--estimate-extrinsic", args->estimate_extrinsic,
                    "Estimate the camera-body extrinsic T_b_c online (docs/vio.md; "
                    "extrinsic.estimate)");
  CLI::Option* estimate_td =
      cmd->add_flag("--estimate-time-offset", args->estimate_time_offset,
                    "Estimate the camera-IMU time offset online (t_imu = t_cam + td; JSON summary "
                    "camera_imu_time_offset_s; time_offset.estimate, keys time_offset.initial_s, "
                    "time_offset.prior_sigma_s)");
  CLI::Option* stride =
      cmd->add_option("--point-stride", args->point_stride,
                      "Use the point tracks whose id is a multiple of this (features folders; "
                      "input.point_stride)")
          ->capture_default_str();
  CLI::Option* window =
      cmd->add_option("--window", args->window, "Keyframes in the window (window.size)")
          ->capture_default_str();
  // Each flag sets its key of the table (vio_config.cc) after --config: one code path.
  const std::vector<OptionFlag> flags = {{no_lines, "use_lines", "false"},
                                         {estimate_extrinsic, "extrinsic.estimate", "true"},
                                         {estimate_td, "time_offset.estimate", "true"},
                                         {stride, "input.point_stride", ""},
                                         {window, "window.size", ""}};
  cmd->add_flag("--quiet", args->quiet, "No progress output (warnings are still printed)");
  cmd->callback([args, exit_code, flags]() {
    RunGuarded("vio", exit_code, [&] {
      CheckVioSources(args->features, args->euroc, args->bag, args->camera);
      if (!args->features.empty() && !args->draw.empty())
        throw std::invalid_argument("--draw needs images (--euroc or --bag)");
      if (!args->draw.empty() && !args->tracks.empty())
        throw std::invalid_argument("--tracks and --draw cannot be given together");
      // The configuration file, then what the command line gives explicitly.
      if (!args->config.empty()) ApplyVioConfig(args->config, &args->cfg);
      ApplyOptionFlags(VioOptions(), flags, &args->cfg);
      CheckVioConfig(args->cfg, args->config.empty() ? "the command line" : args->config);
      return Run(*args);
    });
  });
}

}  // namespace app
}  // namespace plucker
