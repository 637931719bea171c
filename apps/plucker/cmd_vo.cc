// plucker vo: monocular point + line visual odometry, odometry::MonocularOdometry
// (src/plucker/odometry/monocular_odometry.h, docs/vo.md), on a features folder (the sim format,
// docs/sim-format.md: rig.txt, points.txt and segments.txt with track ids; the ground truth in the
// folder is not read), an image folder or a bag's image topic (the pipeline runs the image front
// end; vo_image_input.h). A reader, a
// loop that feeds the frames in order, and writers:
//   --out         KITTI poses T_w_c of every frame, the refined view (Trajectory() after the end of
//                 the input): the frames before a start localised against its map (backfilled),
//                 frames that could not be localised repeat the last pose (marked in the JSON);
//                 world = camera a of the first start, scale |t_ab| = 1;
//   --out-online  KITTI poses as each frame's AddImage/AddFrame returned them (inputs up to that
//                 frame only): a row of nan where the frame had no pose when it arrived (start
//                 search, lost);
//   --json        per-frame statistics, CPU time per stage (front end included), a summary.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <opencv2/core/utility.hpp>
#include <optional>

#include "commands.h"
#include "option_flags.h"
#include "plucker/io/io_error.h"
#include "plucker/io/sim_format.h"
#include "plucker/odometry/monocular_odometry.h"
#include "plucker/sensor/fisheye_rig.h"
#include "process_setup.h"
#include "progress.h"
#include "run_guarded.h"
#include "stage_clock.h"
#include "vio_input.h"
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
  bool stereo = false;      // the folder's second camera (cam1_*.txt)
  bool quiet = false;
};

// --stereo: the second camera's observations of a features folder into the frames (the point
// stride as the left's), and its extrinsic into the window; an error naming rig.txt without one.
void AttachSecondCamera(const std::string& dir, const sensor::CameraImuSequence& seq, int stride,
                        std::vector<window::FrameInput>* frames, VoConfig* config) {
  const std::string rig = (std::filesystem::path(dir) / "rig.txt").string();
  if (!seq.cam1) {
    throw io::IoError(rig,
                      "--stereo: the folder has no second camera (no T_c0_c1 and cam1_counts "
                      "records, no cam1_points.txt / cam1_segments.txt; docs/sim-format.md)");
  }
  if (seq.rig.fisheye) throw io::IoError(rig, "--stereo: fisheye rigs are not supported");
  for (const auto& p : seq.cam1->points)
    if (p.point_id >= 0 && p.point_id % stride == 0) (*frames)[p.frame].right_points.push_back(p);
  for (const auto& s : seq.cam1->segments) (*frames)[s.frame].right_segments.push_back(s);
  config->window.T_c0_c1 = seq.cam1->T_c0_c1;
}

int Run(const VoArgs& a, VoConfig config) {
  SetUpProcess(ImagePipelineSetup(), cv::setNumThreads);  // one thread, front end on the heap
  const double t_start = WallMs();
  std::vector<std::string> inputs = CameraFlagFiles(a.images.camera);
  inputs.insert(inputs.end(), {a.images.bag.bag, a.config});
  RefuseOverwritingInputs(inputs, {a.out, a.out_online, a.json});
  const bool images = a.features.empty();
  std::vector<window::FrameInput> frames;
  std::unique_ptr<VoImageStream> stream;
  std::unique_ptr<odometry::MonocularOdometry> vo;
  if (images) {
    stream = std::make_unique<VoImageStream>(a.images);
    vo = std::make_unique<odometry::MonocularOdometry>(stream->camera(), config);
  } else {
    sensor::CameraImuSequence seq = io::ReadCameraImuSequence(a.features);
    sensor::ToPinholeView(&seq);  // a fisheye rig's raw points into its view (fisheye_rig.h)
    frames = FeatureFrames(seq, a.point_stride);
    if (a.stereo) AttachSecondCamera(a.features, seq, a.point_stride, &frames, &config);
    config.window.point_sigma_px = config.window.line_sigma_px =
        std::max(seq.observation_model.pixel_sigma, 0.5);
    vo = std::make_unique<odometry::MonocularOdometry>(seq.rig.K, config);
  }
  const std::string source = images ? stream->source() : a.features;
  const int n = static_cast<int>(images ? stream->size() : frames.size());
  if (n < 3) throw io::IoError(source, "needs at least 3 frames, has " + std::to_string(n));
  std::vector<std::string> names;  // of the images, for the overlays
  if (!a.draw.empty() && images) {
    std::filesystem::create_directories(a.draw);
    vo->SetFrameObserver([&](int i, const window::FrameInput& f, const SE3d& T,
                             const window::SlidingWindowEstimator& map) {
      WriteVoOverlay(a.draw, names[i], vo->undistorter(), vo->K(), f, i, T, map);
    });
  }
  VoRunLog log;
  log.point_stride = a.point_stride;
  log.read_ms = WallMs() - t_start;
  std::vector<std::optional<SE3d>> online;
  FrameProgress progress("plucker vo", n, a.quiet);
  VoImage image;
  for (int i = 0;; ++i) {
    VoFrameLog f;
    odometry::MonocularFrameResult r;
    if (images) {
      const double t_read = ThreadCpuMs();
      if (!stream->Next(&image)) break;
      f.ms[kRead] = ThreadCpuMs() - t_read;
      if (!a.draw.empty()) names.push_back(image.name);
      f.frontend = {{"image", image.name}};
      if (image.image.empty()) {
        f.frontend["skipped"] = image.problem;
        ++log.skipped_images;
        progress.Break();
        std::cerr << "plucker vo: warning: skipped " << image.problem << "\n";
      }
      VoFrameClock clock;
      r = vo->AddImage(image.t, image.image, clock.frontend.Observer(), clock.window.Observer());
      clock.Into(&f);
      f.frontend["observed_points"] = r.observed_points;
      f.frontend["observed_segments"] = r.observed_segments;
    } else {
      if (i >= n) break;
      VoFrameClock clock;
      r = vo->AddFrame(std::move(frames[i]), clock.window.Observer());
      clock.Into(&f);
    }
    f.online = r.status;
    f.online_pose = r.has_pose;
    online.push_back(r.has_pose ? std::optional<SE3d>(r.T_w_c) : std::nullopt);
    log.frames.push_back(std::move(f));
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
  if (stream)
    for (const std::string& w : stream->warnings())
      std::cerr << "plucker vo: warning: " << w << "\n";
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
      "on a features folder (docs/sim-format.md), an image folder or a bag's image topic");
  CLI::Option* features = cmd->add_option(
      "--features", args->features,
      "Features folder: rig.txt, points.txt, segments.txt with track ids (docs/sim-format.md)");
  CLI::Option* images = cmd->add_option(
      "--images", args->images.images,
      "Image folder (image files in name order; undistorted, or with --sensor distorted)");
  CLI::Option* bag = AddBagFlags(cmd, &args->images.bag, false,
                                 "ROS 1 bag: the images of --image-topic (calibration from "
                                 "--sensor or --calib)");
  features->excludes(images);
  bag->excludes(features)->excludes(images);
  AddCameraFlags(cmd, &args->images.camera, CameraFlagSet{});
  cmd->add_option("--rate", args->images.frame_rate_hz, "Frame rate of --images (frame times)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--out", args->out,
                  "Output KITTI poses T_w_c of every frame, refined (start frames backfilled)")
      ->required();
  cmd->add_option("--out-online", args->out_online,
                  "Output KITTI poses as each frame's result gave them (nan rows: no pose yet)");
  cmd->add_option("--json", args->json, "Per-frame statistics, stage times and a summary (JSON)");
  CLI::Option* no_lines = cmd->add_flag("--no-lines", args->no_lines, "Points only (use_lines)");
  CLI::Option* drop_lines = cmd->add_flag(
      "--drop-marginalized-lines", args->drop_marginalized_lines,
      "Drop the line observations of a marginalized keyframe (what PL-VIO does) instead of "
      "keeping their information in the prior (window.keep_marginalized_lines)");
  CLI::Option* no_fej =
      cmd->add_flag("--no-fej", args->no_fej,
                    "Relinearise every factor (no first-estimate Jacobians for the prior's blocks; "
                    "window.first_estimate_jacobians)");
  CLI::Option* no_conditioning =
      cmd->add_flag("--no-line-conditioning", args->no_line_conditioning,
                    "Lines in the world frame instead of their anchor frame "
                    "(window.condition_far_lines)");
  cmd->add_option("--point-stride", args->point_stride,
                  "Use the point tracks whose id is a multiple of this (scarce points)")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  CLI::Option* window =
      cmd->add_option("--window", args->window, "Keyframes in the window (window.size)")
          ->capture_default_str();
  CLI::Option* iterations =
      cmd->add_option("--iterations", args->iterations,
                      "Solver iterations per window solve (window.iterations)")
          ->capture_default_str();
  CLI::Option* line_min_angle =
      cmd->add_option(
             "--line-min-angle", args->line_min_angle_deg,
             "Smallest angle between the back-projected planes of a new line (deg; 10 with "
             "--images; window.line_min_angle_deg)")
          ->capture_default_str();
  CLI::Option* loss_scale = cmd->add_option("--loss-scale", args->loss_scale,
                                            "Huber loss scale (in pixel sigmas; window.loss_scale)")
                                ->capture_default_str();
  cmd->add_option("--config", args->config,
                  "YAML file of options (`plucker config vo` prints them all with their ranges; "
                  "docs/vo.md); a flag given on the command line overrides its key")
      ->check(CLI::ExistingFile);
  cmd->add_option("--draw", args->draw,
                  "Folder for one PNG per frame: tracked points and segments, reprojected 3D lines "
                  "(--images only)");
  CLI::Option* max_lost =
      cmd->add_option("--max-lost", args->max_lost_frames,
                      "Lost frames in a row before a new two-view start (re-initialisation; "
                      "init.max_lost_frames)")
          ->capture_default_str();
  // Each flag sets its key of the table (vo_config.cc) after --config: one code path.
  const std::vector<OptionFlag> flags = {{window, "window.size", ""},
                                         {iterations, "window.iterations", ""},
                                         {loss_scale, "window.loss_scale", ""},
                                         {line_min_angle, "window.line_min_angle_deg", ""},
                                         {no_lines, "use_lines", "false"},
                                         {drop_lines, "window.keep_marginalized_lines", "false"},
                                         {no_fej, "window.first_estimate_jacobians", "false"},
                                         {no_conditioning, "window.condition_far_lines", "false"},
                                         {max_lost, "init.max_lost_frames", ""}};
  cmd->add_flag("--stereo", args->stereo,
                "Stereo VO with metric scale: the features folder's second camera (cam1_*.txt, "
                "T_c0_c1 in rig.txt; `plucker sim camera --stereo`; docs/vo.md)")
      ->needs(features);
  cmd->add_flag("--quiet", args->quiet, "No progress output (warnings are still printed)");
  cmd->callback([args, exit_code, flags]() {
    RunGuarded("vo", exit_code, [&] {
      CheckVoSources(args->features, args->images, args->draw);
      // Defaults (images: ImageVoConfig), then the file, then the flags given.
      VoConfig config = args->features.empty() ? ImageVoConfig() : FeaturesVoConfig();
      if (!args->config.empty()) LoadVoConfig(args->config, &config);
      ApplyOptionFlags(VoOptions(), flags, &config);
      return Run(*args, config);
    });
  });
}

}  // namespace app
}  // namespace plucker
