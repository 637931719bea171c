// plucker vo: monocular point + line visual odometry with the sliding-window estimator
// (src/plucker/window, docs/vo.md) on a features folder (the sim format, docs/sim-format.md:
// rig.txt, points.txt and segments.txt with track ids; the ground truth in the folder is not read
// by the estimator). The pipeline reads as the algorithm:
//   initialise  two-view essential matrix on the point tracks of frame a and a later frame b with
//               enough parallax (scale: |t_ab| = 1, arbitrary), triangulation, first window solve;
//   localize    the frames between a and b (and before a) against that first map;
//   per frame   window AddFrame: track, keyframe decision, triangulate, solve, marginalize.
// Writes the KITTI poses T_w_c of every frame (world = camera a; frames that could not be localised
// repeat the last pose and are marked in the JSON).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.h"
#include "plucker/io/io_error.h"
#include "plucker/io/sim_format.h"
#include "plucker/io/trajectory_io.h"
#include "plucker/window/sliding_window_estimator.h"
#include "plucker/window/two_view_initialization.h"
#include "stage_clock.h"
#include "vo_image_input.h"

namespace plucker {
namespace app {
namespace {

struct VoArgs {
  std::string features, out, json;
  VoImageSource images;
  bool no_lines = false;
  bool drop_marginalized_lines = false;
  bool no_fej = false;
  bool no_line_conditioning = false;
  int point_stride = 1;
  int window = 10;
  int iterations = 10;
  int max_init_gap = 30;
  double line_min_angle_deg = 5.0;
  double loss_scale = 1.5;
  double keyframe_parallax_px = 10.0;
  double min_tracked_ratio = 0.6;
  std::string prior = "landmarks";
  std::string solver = "sparse_schur";
  bool quiet = false;
};

const char* kStageNames[window::kNumWindowStages] = {"tracking", "triangulation", "solve",
                                                     "marginalization"};

// The frames of the sequence as estimator input; point tracks kept when id % stride == 0.
std::vector<window::FrameInput> Frames(const sensor::CameraImuSequence& seq, int stride) {
  std::vector<window::FrameInput> frames(seq.frame_times.size());
  for (std::size_t i = 0; i < frames.size(); ++i) frames[i].time = seq.frame_times[i];
  for (const auto& p : seq.points)
    if (p.point_id >= 0 && p.point_id % stride == 0) frames[p.frame].points.push_back(p);
  for (const auto& s : seq.segments) frames[s.frame].segments.push_back(s);
  return frames;
}

SE3d Interpolate(const SE3d& a, const SE3d& b, double s) {
  return SE3d(a.rotation().slerp(s, b.rotation()),
              (1.0 - s) * a.translation() + s * b.translation());
}

// The estimator's input from either source: a features folder or images through the front end.
struct VoInput {
  PinholeIntrinsics K;
  double pixel_sigma = 1.0;
  std::vector<window::FrameInput> frames;
  std::vector<nlohmann::json> info;  // per frame, from the front end (empty for features)
  nlohmann::json frontend_ms;        // mean per frame by stage (images)
  std::vector<std::string> warnings;
};

VoInput ReadInput(const VoArgs& a) {
  VoInput in;
  if (a.images.images.empty()) {
    const sensor::CameraImuSequence seq = io::ReadCameraImuSequence(a.features);
    in.K = seq.rig.K;
    in.pixel_sigma = seq.observation_model.pixel_sigma;
    in.frames = Frames(seq, a.point_stride);
    in.info.resize(in.frames.size());
    return in;
  }
  VoImageSource source = a.images;
  source.use_lines = !a.no_lines;
  source.quiet = a.quiet;
  VoImageInput images = ReadVoImages(source);
  in.K = images.K;
  in.frames = std::move(images.frames);
  in.info = std::move(images.info);
  in.frontend_ms = images.mean_stage_ms;
  in.warnings = std::move(images.warnings);
  return in;
}

int Run(const VoArgs& a) {
  const double t_start = WallMs();
  const VoInput input = ReadInput(a);
  const std::string source = a.images.images.empty() ? a.features : a.images.images;
  const std::vector<window::FrameInput>& frames = input.frames;
  const int n = static_cast<int>(frames.size());
  if (n < 3) throw io::IoError(source, "needs at least 3 frames, has " + std::to_string(n));
  for (const std::string& w : input.warnings)
    std::cerr << "plucker vo: warning: skipped " << w << "\n";
  const double read_ms = WallMs() - t_start;

  window::SlidingWindowOptions options;
  options.window_size = a.window;
  options.max_iterations = a.iterations;
  options.use_lines = !a.no_lines;
  options.keep_marginalized_lines = !a.drop_marginalized_lines;
  options.first_estimate_jacobians = !a.no_fej;
  options.condition_far_lines = !a.no_line_conditioning;
  options.line_triangulation.min_plane_angle_deg = a.line_min_angle_deg;
  options.loss_scale = a.loss_scale;
  options.keyframe_parallax_px = a.keyframe_parallax_px;
  options.min_tracked_ratio = a.min_tracked_ratio;
  options.prior_blocks = a.prior == "poses" ? window::SlidingWindowOptions::PriorBlocks::kPoses
                                            : window::SlidingWindowOptions::PriorBlocks::kLandmarks;
  options.point_sigma_px = options.line_sigma_px = std::max(input.pixel_sigma, 0.5);
  window::SlidingWindowEstimator estimator(input.K, options);

  std::vector<SE3d> poses(n);
  std::vector<nlohmann::json> per_frame(n);
  std::vector<std::string> status(n, "not_localized");
  // Initialise: the first pair (a, b) with enough parallax.
  const double t_init = ThreadCpuMs();
  int first = -1, second = -1;
  std::string init_message = "no frame pair";
  for (int i = 0; i + 1 < n && first < 0; ++i) {
    for (int j = i + 1; j < n && j <= i + a.max_init_gap; ++j) {
      const window::TwoViewResult tv =
          window::InitializeTwoView(input.K, frames[i].points, frames[j].points);
      if (!tv.ok) {
        init_message = "frames " + std::to_string(i) + "-" + std::to_string(j) + ": " + tv.message;
        continue;
      }
      const window::InitializationResult init =
          estimator.Initialize(frames[i], SE3d(), frames[j], tv.T_b_a.Inverse());
      if (!init.ok) {
        init_message = "frames " + std::to_string(i) + "-" + std::to_string(j) +
                       ": too few landmarks triangulated";
        continue;
      }
      first = i;
      second = j;
      poses[i] = init.T_w_a;
      poses[j] = init.T_w_b;
      break;
    }
  }
  const double init_ms = ThreadCpuMs() - t_init;
  if (first < 0) {
    throw io::IoError(
        source, "cannot initialise (" + init_message + "): too few point tracks with parallax");
  }
  status[first] = status[second] = "initialization";
  for (int i = 0; i < second; ++i) {
    if (i == first) continue;
    const SE3d guess = i < first ? poses[first]
                                 : Interpolate(poses[first], poses[second],
                                               double(i - first) / double(second - first));
    const std::optional<SE3d> T = estimator.Localize(frames[i], guess);
    poses[i] = T.value_or(guess);
    status[i] = T ? "localized_before_window" : "not_localized";
  }

  int keyframes = 2, lost = 0, marginalized = 0, failed_marginalizations = 0;
  std::array<double, window::kNumWindowStages> stage_total{};
  double frame_total = 0.0;
  double last_progress = WallMs();
  for (int i = second + 1; i < n; ++i) {
    BasicStageClock<window::WindowStage, window::kNumWindowStages> ms;
    const double t0 = ThreadCpuMs();
    const window::FrameResult r = estimator.AddFrame(frames[i], ms.Observer());
    const double frame_ms = ThreadCpuMs() - t0;
    frame_total += frame_ms;
    for (int s = 0; s < window::kNumWindowStages; ++s) stage_total[s] += ms.ms(s);
    const bool finite =
        r.T_w_c.translation().allFinite() && r.T_w_c.rotation().coeffs().allFinite();
    poses[i] = finite ? r.T_w_c : poses[i - 1];
    status[i] = r.ok && finite ? "tracked" : "lost";
    keyframes += r.keyframe;
    lost += !(r.ok && finite);
    marginalized += r.marginalized_keyframes;
    failed_marginalizations += r.marginalization_failed;
    nlohmann::json times = {{"total", frame_ms}};
    for (int s = 0; s < window::kNumWindowStages; ++s) times[kStageNames[s]] = ms.ms(s);
    per_frame[i] = {{"keyframe", r.keyframe},
                    {"tracked_points", r.tracked_points},
                    {"tracked_lines", r.tracked_lines},
                    {"new_points", r.new_points},
                    {"new_lines", r.new_lines},
                    {"window_points", r.window_points},
                    {"window_lines", r.window_lines},
                    {"window_keyframes", r.window_keyframes},
                    {"parallax_px", r.parallax_px},
                    {"tracking_iterations", r.tracking_iterations},
                    {"window_iterations", r.window_iterations},
                    {"initial_cost", r.initial_cost},
                    {"final_cost", r.final_cost},
                    {"residuals", r.residuals},
                    {"culled_observations", r.culled_observations},
                    {"marginalized_keyframes", r.marginalized_keyframes},
                    {"marginalized_landmarks", r.marginalized_landmarks},
                    {"dropped_line_observations", r.dropped_line_observations},
                    {"prior_rank", r.prior_rank},
                    {"marginalization_failed", r.marginalization_failed},
                    {"ms", times}};
    const double now = WallMs();
    if (!a.quiet && (now - last_progress > 500.0 || i + 1 == n)) {
      last_progress = now;
      std::cerr << "\rplucker vo: frame " << (i + 1) << "/" << n << "  keyframes " << keyframes
                << "  points " << r.window_points << "  lines " << r.window_lines << "   "
                << std::flush;
    }
  }
  if (!a.quiet) std::cerr << "\n";
  io::WriteKittiPoses(a.out, poses);
  const double total_ms = WallMs() - t_start;
  const int window_frames = n - second - 1;
  if (!a.json.empty()) {
    nlohmann::json out;
    nlohmann::json list = nlohmann::json::array();
    for (int i = 0; i < n; ++i) {
      nlohmann::json f = per_frame[i].is_null() ? nlohmann::json::object() : per_frame[i];
      if (!input.info[i].is_null()) f["frontend"] = input.info[i];
      f["frame"] = i;
      f["time"] = frames[i].time;
      f["status"] = status[i];
      if (i == first || i == second) f["keyframe"] = true;
      list.push_back(f);
    }
    nlohmann::json stages = nlohmann::json::object();
    for (int s = 0; s < window::kNumWindowStages; ++s)
      stages[kStageNames[s]] = window_frames > 0 ? stage_total[s] / window_frames : 0.0;
    out["frames"] = list;
    out["summary"] = {
        {"frames", n},
        {"initialization_frames", {first, second}},
        {"keyframes", keyframes},
        {"lost_frames", lost},
        {"marginalized_keyframes", marginalized},
        {"failed_marginalizations", failed_marginalizations},
        {"use_lines", !a.no_lines},
        {"keep_marginalized_lines", !a.drop_marginalized_lines},
        {"point_stride", a.point_stride},
        {"read_ms", read_ms},
        {"frontend_mean_ms", input.frontend_ms},
        {"skipped_images", input.warnings.size()},
        {"initialization_ms", init_ms},
        {"mean_frame_ms", window_frames > 0 ? frame_total / window_frames : 0.0},
        {"mean_stage_ms", stages},
        {"total_wall_ms", total_ms},
        {"frames_per_second_cpu", frame_total > 0 ? 1e3 * window_frames / frame_total : 0.0}};
    io::WriteFileAtomically(a.json, out.dump(1) + "\n");
  }
  if (!a.quiet) {
    std::cerr << "plucker vo: " << n << " frames (initialised on frames " << first << " and "
              << second << "), " << keyframes << " keyframes, " << lost << " lost, " << std::fixed
              << std::setprecision(2) << (window_frames > 0 ? frame_total / window_frames : 0.0)
              << " ms CPU per frame; wrote " << a.out << "\n";
  }
  if (lost > 0) {
    std::cerr << "plucker vo: warning: " << lost
              << " frames could not be tracked (their pose is the constant-velocity prediction, or "
                 "the previous pose)\n";
  }
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
  cmd->add_option("--out", args->out, "Output KITTI poses T_w_c of every frame")->required();
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
  cmd->add_option("--window", args->window, "Keyframes in the window")
      ->check(CLI::Range(2, 1000))
      ->capture_default_str();
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
  cmd->add_option("--loss-scale", args->loss_scale, "Huber loss scale (in pixel sigmas)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--keyframe-parallax", args->keyframe_parallax_px, "Keyframe parallax (px)")
      ->capture_default_str();
  cmd->add_option("--min-tracked-ratio", args->min_tracked_ratio, "Keyframe track ratio")
      ->capture_default_str();
  cmd->add_option("--prior", args->prior, "Prior blocks: landmarks or poses")
      ->check(CLI::IsMember({"landmarks", "poses"}))
      ->capture_default_str();
  cmd->add_option("--max-points", args->images.frontend.points.target_count, "Point tracks")
      ->capture_default_str();
  cmd->add_option("--point-distance", args->images.frontend.points.min_distance_px,
                  "Point min distance")
      ->capture_default_str();
  cmd->add_flag("--quiet", args->quiet, "No progress output (warnings are still printed)");
  cmd->callback([args, exit_code, line_min_angle]() {
    try {
      // Real images (a car or a walker moving forward): lines along the motion are seen from
      // nearly the same plane; 10 deg keeps them out (on the KITTI clip 5 deg made the ATE 7x
      // worse than points alone, 10 deg equal to it).
      if (!args->images.images.empty() && line_min_angle->count() == 0) {
        args->line_min_angle_deg = 10.0;
      }
      const VoImageSource& im = args->images;
      if (args->features.empty() == im.images.empty()) {
        throw std::invalid_argument("give --features DIR or --images DIR");
      }
      if (!im.images.empty() && im.calib.empty() == im.sensor.empty()) {
        throw std::invalid_argument("--images needs --calib calib.txt or --sensor sensor.yaml");
      }
      *exit_code = Run(*args);
    } catch (const std::exception& e) {
      std::cerr << "plucker vo: error: " << e.what() << "\n";
      *exit_code = 1;
    }
  });
}

}  // namespace app
}  // namespace plucker
