// plucker vo: monocular point + line visual odometry, odometry::MonocularOdometry
// (src/plucker/odometry/monocular_odometry.h, docs/vo.md), on a features folder (the sim format,
// docs/sim-format.md: rig.txt, points.txt and segments.txt with track ids; the ground truth in the
// folder is not read) or on an image folder (the pipeline runs the image front end). A reader, a
// loop that feeds the frames in order, and writers:
//   --out         KITTI poses T_w_c of every frame, the refined view (Trajectory() after the end of
//                 the input): the frames before a start localised against its map (backfilled),
//                 frames that could not be localised repeat the last pose (marked in the JSON);
//                 world = camera a of the first start, scale |t_ab| = 1;
//   --out-online  KITTI poses as each frame's AddImage/AddFrame returned them (inputs up to that
//                 frame only): a row of nan where the frame had no pose when it arrived (start
//                 search, lost);
//   --json        per-frame statistics, CPU time per stage (front end included), a summary.
#include <malloc.h>
#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <opencv2/core/utility.hpp>
#include <optional>

#include "commands.h"
#include "plucker/io/io_error.h"
#include "plucker/io/sim_format.h"
#include "plucker/odometry/monocular_odometry.h"
#include "progress.h"
#include "run_guarded.h"
#include "stage_clock.h"
#include "vo_config.h"
#include "vo_draw.h"
#include "vo_image_input.h"
#include "vo_output.h"

namespace plucker {
namespace app {
namespace {

struct VoArgs {
  std::string features, out, out_online, json, draw, config;
  VoImageSource images;
  bool no_lines = false;
  bool drop_marginalized_lines = false;
  bool no_fej = false;
  bool no_line_conditioning = false;
  int point_stride = 1;
  int window = 10;
  int iterations = 10;
  double line_min_angle_deg = 5.0;
  double loss_scale = 1.5;
  int max_lost_frames = 3;  // consecutive lost frames before a re-initialisation
  bool quiet = false;
};

int Run(const VoArgs& a, VoConfig config) {
  // One thread: OpenCV's own pool (KLT, corners, RANSAC) off; Ceres runs with num_threads = 1.
  cv::setNumThreads(0);
  // The front end allocates MB-sized temporaries per image (corner responses, pyramids): served
  // by fresh mmaps, each page faults again every frame (measured: 40 ms of 48 in the points
  // stage of --no-lines on KITTI). Keep them on the heap.
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 128 << 20);
  const double t_start = WallMs();
  const bool images = !a.images.images.empty();
  const std::string source = images ? a.images.images : a.features;
  std::vector<window::FrameInput> frames;
  VoImageFolder folder;
  std::unique_ptr<odometry::MonocularOdometry> vo;
  if (images) {
    folder = OpenVoImages(a.images);
    vo = std::make_unique<odometry::MonocularOdometry>(folder.camera, config);
  } else {
    const sensor::CameraImuSequence seq = io::ReadCameraImuSequence(a.features);
    frames = VoFeatureFrames(seq, a.point_stride);
    config.window.point_sigma_px = config.window.line_sigma_px =
        std::max(seq.observation_model.pixel_sigma, 0.5);
    vo = std::make_unique<odometry::MonocularOdometry>(seq.rig.K, config);
  }
  const int n = static_cast<int>(images ? folder.files.size() : frames.size());
  if (n < 3) throw io::IoError(source, "needs at least 3 frames, has " + std::to_string(n));
  if (!a.draw.empty() && images) {
    std::filesystem::create_directories(a.draw);
    vo->SetFrameObserver([&](int i, const window::FrameInput& f, const SE3d& T,
                             const window::SlidingWindowEstimator& map) {
      WriteVoOverlay(a.draw, folder.files[i], vo->undistorter(), vo->K(), f, i, T, map);
    });
  }
  VoRunLog log;
  log.point_stride = a.point_stride;
  log.read_ms = WallMs() - t_start;
  log.frames.resize(n);
  std::vector<std::optional<SE3d>> online(n);
  FrameProgress progress("plucker vo", n, a.quiet);
  for (int i = 0; i < n; ++i) {
    VoFrameLog& f = log.frames[i];
    odometry::MonocularFrameResult r;
    if (images) {
      std::string problem;
      const double t_read = ThreadCpuMs();
      const cv::Mat image = ReadVoImage(folder.files[i], folder.camera, &problem);
      f.ms[kRead] = ThreadCpuMs() - t_read;
      f.frontend = {{"image", folder.files[i]}};
      if (image.empty()) {
        f.frontend["skipped"] = problem;
        ++log.skipped_images;
        progress.Break();
        std::cerr << "plucker vo: warning: skipped " << problem << "\n";
      }
      VoFrameClock clock;
      r = vo->AddImage(double(i) / a.images.frame_rate_hz, image, clock.frontend.Observer(),
                       clock.window.Observer());
      clock.Into(&f);
      f.frontend["observed_points"] = r.observed_points;
      f.frontend["observed_segments"] = r.observed_segments;
    } else {
      VoFrameClock clock;
      r = vo->AddFrame(std::move(frames[i]), clock.window.Observer());
      clock.Into(&f);
    }
    f.online = r.status;
    f.online_pose = r.has_pose;
    if (r.has_pose) online[i] = r.T_w_c;
    if (r.status == odometry::MonocularStatus::kReinitialized && !a.quiet) {
      progress.Break();
      std::cerr << "plucker vo: re-initialised on frames " << vo->Maps().back().first << " and "
                << vo->Maps().back().second << "\n";
    }
    if (progress.Due(i)) {
      progress.Show(i, "keyframes " + std::to_string(vo->Summary().keyframes) + "  lost " +
                           std::to_string(vo->Summary().lost_frames));
    }
  }
  BasicStageClock<window::WindowStage, window::kNumWindowStages> finish_clock;
  const double t_finish = ThreadCpuMs();
  vo->Finish(finish_clock.Observer());
  log.finish_ms = ThreadCpuMs() - t_finish;
  progress.Break();
  log.total_wall_ms = WallMs() - t_start;
  WriteVoOutputs(VoOutputs{a.out, a.out_online, a.json, source, a.quiet}, *vo, config, online, log);
  return 0;
}

}  // namespace

void RegisterVo(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<VoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "vo",
      "Monocular point + line visual odometry (sliding window with marginalization, docs/vo.md) "
      "on a features folder (docs/sim-format.md)");
  CLI::Option* features = cmd->add_option(
      "--features", args->features,
      "Features folder: rig.txt, points.txt, segments.txt with track ids (docs/sim-format.md)");
  CLI::Option* images = cmd->add_option(
      "--images", args->images.images,
      "Image folder (image files in name order; undistorted, or with --sensor distorted)");
  features->excludes(images);
  cmd->add_option("--calib", args->images.calib, "KITTI calib.txt (P0) of --images")
      ->check(CLI::ExistingFile);
  cmd->add_option("--sensor", args->images.sensor,
                  "EuRoC cam0 sensor.yaml of --images (radial-tangential: undistorted first)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--rate", args->images.frame_rate_hz, "Frame rate of --images (frame times)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--out", args->out,
                  "Output KITTI poses T_w_c of every frame, refined (start frames backfilled)")
      ->required();
  cmd->add_option("--out-online", args->out_online,
                  "Output KITTI poses as each frame's result gave them (nan rows: no pose yet)");
  cmd->add_option("--json", args->json, "Per-frame statistics, stage times and a summary (JSON)");
  cmd->add_flag("--no-lines", args->no_lines, "Points only");
  cmd->add_flag("--drop-marginalized-lines", args->drop_marginalized_lines,
                "Drop the line observations of a marginalized keyframe (what PL-VIO does) "
                "instead of keeping their information in the prior");
  cmd->add_flag("--no-fej", args->no_fej,
                "Relinearise every factor (no first-estimate Jacobians for the prior's blocks)");
  cmd->add_flag("--no-line-conditioning", args->no_line_conditioning,
                "Lines in the world frame instead of their anchor frame");
  cmd->add_option("--point-stride", args->point_stride,
                  "Use the point tracks whose id is a multiple of this (scarce points)")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  CLI::Option* window = cmd->add_option("--window", args->window, "Keyframes in the window")
                            ->check(CLI::Range(2, 1000))
                            ->capture_default_str();
  CLI::Option* iterations =
      cmd->add_option("--iterations", args->iterations, "Solver iterations per window solve")
          ->check(CLI::Range(1, 1000))
          ->capture_default_str();
  CLI::Option* line_min_angle =
      cmd->add_option(
             "--line-min-angle", args->line_min_angle_deg,
             "Smallest angle between the back-projected planes of a new line (deg; 10 with "
             "--images)")
          ->check(CLI::Range(0.0, 90.0))
          ->capture_default_str();
  CLI::Option* loss_scale =
      cmd->add_option("--loss-scale", args->loss_scale, "Huber loss scale (in pixel sigmas)")
          ->check(CLI::PositiveNumber)
          ->capture_default_str();
  cmd->add_option("--config", args->config,
                  "YAML file of window and front-end options (keys: docs/vo.md); "
                  "flags given on the command line override it")
      ->check(CLI::ExistingFile);
  cmd->add_option("--draw", args->draw,
                  "Folder for one PNG per frame: tracked points and segments, reprojected 3D lines "
                  "(--images only)");
  cmd->add_option("--max-lost", args->max_lost_frames,
                  "Lost frames in a row before a new two-view start (re-initialisation)")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_flag("--quiet", args->quiet, "No progress output (warnings are still printed)");
  cmd->callback([args, exit_code, line_min_angle, window, iterations, loss_scale]() {
    RunGuarded("vo", exit_code, [&] {
      const VoImageSource& im = args->images;
      if (args->features.empty() == im.images.empty()) {
        throw std::invalid_argument("give --features DIR or --images DIR");
      }
      if (!im.images.empty() && im.calib.empty() == im.sensor.empty()) {
        throw std::invalid_argument("--images needs --calib calib.txt or --sensor sensor.yaml");
      }
      // Defaults (images: ImageVoConfig), then the file, then the flags given.
      VoConfig config = im.images.empty() ? FeaturesVoConfig() : ImageVoConfig();
      if (!args->config.empty()) LoadVoConfig(args->config, &config);
      window::SlidingWindowOptions& w = config.window;
      if (window->count()) w.window_size = args->window;
      if (iterations->count()) w.max_iterations = args->iterations;
      if (loss_scale->count()) w.loss_scale = args->loss_scale;
      if (line_min_angle->count())
        w.line_triangulation.min_plane_angle_deg = args->line_min_angle_deg;
      if (args->no_lines) w.use_lines = false;
      if (args->drop_marginalized_lines) w.keep_marginalized_lines = false;
      if (args->no_fej) w.first_estimate_jacobians = false;
      if (args->no_line_conditioning) w.condition_far_lines = false;
      config.max_lost_frames = args->max_lost_frames;
      return Run(*args, config);
    });
  });
}

}  // namespace app
}  // namespace plucker
