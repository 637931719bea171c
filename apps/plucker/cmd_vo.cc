// plucker vo: monocular point + line visual odometry with the sliding-window estimator
// (src/plucker/window, docs/vo.md) on a features folder (the sim format, docs/sim-format.md:
// rig.txt, points.txt and segments.txt with track ids; the ground truth in the folder is not read
// by the estimator). The pipeline reads as the algorithm:
//   initialise  two-view essential matrix on the point tracks of frame a and a later frame b with
//               enough parallax (scale: |t_ab| = 1, arbitrary), the widest such b first; the
//               frames between localised and solved with a and b as keyframes (points and
//               lines); the first start whose solve passes a chi-square test, else the best;
//   localize    the frames between a and b (and before a) against that first map;
//   per frame   window AddFrame: track, keyframe decision, triangulate, solve, marginalize.
// Writes the KITTI poses T_w_c of every frame (world = camera a; frames that could not be localised
// repeat the last pose and are marked in the JSON).
#include <malloc.h>
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <sstream>

#include "commands.h"
#include "plucker/io/image_folder.h"
#include "plucker/io/io_error.h"
#include "plucker/io/sim_format.h"
#include "plucker/io/trajectory_io.h"
#include "plucker/window/sliding_window_estimator.h"
#include "plucker/window/two_view_initialization.h"
#include "run_guarded.h"
#include "stage_clock.h"
#include "vo_config.h"
#include "vo_draw.h"
#include "vo_image_input.h"

namespace plucker {
namespace app {
namespace {

struct VoArgs {
  std::string features, out, json, draw, config;
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
  std::shared_ptr<const vision::Undistorter> undistorter;  // images with --sensor
};

VoInput ReadInput(const VoArgs& a, const VoConfig& config) {
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
  source.frontend = config.frontend;
  source.use_lines = config.frontend.use_lines && config.window.use_lines;
  source.quiet = a.quiet;
  VoImageInput images = ReadVoImages(source);
  in.K = images.K;
  in.frames = std::move(images.frames);
  in.info = std::move(images.info);
  in.frontend_ms = images.mean_stage_ms;
  in.warnings = std::move(images.warnings);
  in.undistorter = images.undistorter;
  return in;
}

// The state of one run: the trajectory so far, per-frame records, the current map.
struct VoRun {
  const VoArgs& args;
  const VoConfig& config;
  const VoInput& input;
  std::string source;
  int n = 0;
  std::vector<SE3d> poses;
  std::vector<bool> has_pose;  // localised (tracked, initialisation or before the window)
  std::vector<nlohmann::json> per_frame;
  std::vector<std::string> status;
  std::vector<bool> keyframe;
  std::unique_ptr<window::SlidingWindowEstimator> estimator;
  nlohmann::json maps = nlohmann::json::array();  // one entry per (re-)initialisation
  int keyframes = 0, lost = 0, marginalized = 0, failed_marginalizations = 0;
  int pnp_recoveries = 0;
  int window_frames = 0;
  double init_ms = 0.0, frame_total = 0.0;
  std::array<double, window::kNumWindowStages> stage_total{};

  VoRun(const VoArgs& a, const VoConfig& c, const VoInput& in)
      : args(a), config(c), input(in), n(static_cast<int>(in.frames.size())) {
    source = a.images.images.empty() ? a.features : a.images.images;
    poses.resize(n);
    has_pose.assign(n, false);
    per_frame.resize(n);
    status.assign(n, "not_localized");
    keyframe.assign(n, false);
  }
};

// The scale of a new map chained to the previous one: the distance the last tracked frames moved
// per frame, times the frame gap of the two views (monocular: the best there is without another
// sensor). nullopt for the first map or without two localised frames before `from`.
std::optional<double> ChainedBaseline(const VoRun& run, int from, int gap) {
  int last = from - 1;
  while (last >= 1 && !(run.has_pose[last] && run.has_pose[last - 1])) --last;
  if (last < 1) return std::nullopt;
  const double step = (run.poses[last].translation() - run.poses[last - 1].translation()).norm();
  if (!(step > 0.0) || !std::isfinite(step)) return std::nullopt;
  return step * gap;
}

// The pose of frame i extrapolated at constant velocity from the last two localised frames
// before `from` (the first map: identity).
SE3d PredictPose(const VoRun& run, int from, int i) {
  int last = from - 1;
  while (last >= 1 && !(run.has_pose[last] && run.has_pose[last - 1])) --last;
  if (last < 1) return SE3d();
  const SE3d step = run.poses[last - 1].Inverse() * run.poses[last];
  SE3d T = run.poses[last];
  for (int k = last; k < i; ++k) T = T * step;
  return T;
}

// The multi-view start: the frames between the two views a = frames[0] and b = frames[1] (at
// most window_size - 3 of them, evenly spaced), localised against the two-view map, become
// keyframes, and one window solve of all of them with their points and lines replaces the two-view
// map (with few points, two views leave the relative pose poorly conditioned and lines constrain
// nothing; three or more views of the lines do). Keeps the two-view map when fewer than one frame
// localises or the solve fails.
void MultiViewStart(const VoRun& run, const window::SlidingWindowOptions& options,
                    std::unique_ptr<window::SlidingWindowEstimator>* estimator,
                    std::vector<int>* start_frames, window::InitializationResult* init_out) {
  const std::vector<window::FrameInput>& frames = run.input.frames;
  const int a = (*start_frames)[0], b = (*start_frames)[1];
  const std::vector<SE3d> ab = (*estimator)->KeyframePoses();
  const int between = std::min(b - a - 1, options.window_size - 3);
  if (between < 1) return;
  std::vector<int> kf = {a};
  std::vector<window::FrameInput> kf_frames = {frames[a]};
  std::vector<SE3d> kf_poses = {ab.front()};
  for (int k = 1; k <= between; ++k) {
    const int m = a + static_cast<int>(std::lround(double(k) * (b - a) / (between + 1)));
    if (m <= kf.back() || m >= b) continue;
    const SE3d guess = Interpolate(ab.front(), ab.back(), double(m - a) / double(b - a));
    const std::optional<SE3d> T = (*estimator)->Localize(frames[m], guess);
    if (!T) continue;
    kf.push_back(m);
    kf_frames.push_back(frames[m]);
    kf_poses.push_back(*T);
  }
  if (kf.size() < 2) return;
  kf.push_back(b);
  kf_frames.push_back(frames[b]);
  kf_poses.push_back(ab.back());
  auto multi = std::make_unique<window::SlidingWindowEstimator>(run.input.K, options);
  const window::InitializationResult init = multi->Initialize(kf_frames, kf_poses);
  if (!init.ok) return;
  *estimator = std::move(multi);
  *init_out = init;
  *start_frames = kf;
}

// One start on the pair (i, j): the two-view map, then (init.multi_view) the multi-view solve.
struct Start {
  std::unique_ptr<window::SlidingWindowEstimator> estimator;
  std::vector<int> start_frames;  // keyframes, oldest first
  window::InitializationResult init;
  std::optional<double> chained;
  // The chi-square test of the start's solve: (chi2 - dof) / sqrt(2 dof) of its whitened
  // residuals (chi2 = 2 cost), about N(0, 1) for a start that fits at the noise level.
  double chi2_z = 0.0;
};

std::optional<Start> TryStart(const VoRun& run, int from, int i, int j,
                              const window::TwoViewResult& tv, std::string* message) {
  const std::vector<window::FrameInput>& frames = run.input.frames;
  Start s;
  s.chained = ChainedBaseline(run, from, j - i);
  const SE3d T_w_a = s.chained ? PredictPose(run, from, i) : SE3d();
  SE3d T_a_b = tv.T_b_a.Inverse();
  if (s.chained) T_a_b = SE3d(T_a_b.rotation(), T_a_b.translation() * *s.chained);
  s.estimator = std::make_unique<window::SlidingWindowEstimator>(run.input.K, run.config.window);
  s.init = s.estimator->Initialize(frames[i], T_w_a, frames[j], T_w_a * T_a_b);
  if (!s.init.ok) {
    *message = "frames " + std::to_string(i) + "-" + std::to_string(j) +
               ": too few landmarks triangulated";
    return std::nullopt;
  }
  s.start_frames = {i, j};
  if (run.config.multi_view_start)
    MultiViewStart(run, run.config.window, &s.estimator, &s.start_frames, &s.init);
  // Degrees of freedom: 2 per residual block, less 6 per pose but the held first, 3 per point,
  // 4 per line and 1 for the free scale.
  const int kf = static_cast<int>(s.start_frames.size());
  const int dof = 2 * s.init.residuals - (6 * (kf - 1) - 1 + 3 * s.init.points + 4 * s.init.lines);
  s.chi2_z = dof > 0 ? (2.0 * s.init.final_cost - dof) / std::sqrt(2.0 * dof)
                     : std::numeric_limits<double>::infinity();
  return s;
}

// Initialise: a new estimator on the first frame a >= from with a second view b (a < b <= a +
// max_gap) whose point tracks give a two-view start, b chosen as TryStart's comments say (features
// folders: the widest pair whose multi-view solve passes the chi-square test; images: the first
// pair that passes the two-view test). The first map's world is camera a with |t_ab| = 1; a later
// map continues the trajectory: camera a at its predicted pose, |t_ab| chained (ChainedBaseline).
// Returns (a, b), or nullopt with the reason in *message.
std::optional<std::pair<int, int>> StartMap(VoRun& run, int from, std::string* message) {
  const std::vector<window::FrameInput>& frames = run.input.frames;
  const double t0 = ThreadCpuMs();
  *message = "no frame pair";
  for (int i = from; i + 1 < run.n; ++i) {
    // Accept the first start whose solve fits at the noise level; after max_tries, the best.
    std::optional<Start> best;
    int tries = 0;
    const auto consider = [&](int j, const window::TwoViewResult& tv) {
      std::optional<Start> start = TryStart(run, from, i, j, tv, message);
      if (!start) return false;
      ++tries;
      if (!best || start->chi2_z < best->chi2_z) best = std::move(start);
      return best->chi2_z <= run.config.max_init_chi2_z || tries >= run.config.max_init_tries;
    };
    // The widest pair first (all pairs tested, then tried from the widest): under forward motion
    // with few points, short pairs' five-point solutions are often wrong (docs/vo.md, "The start
    // with scarce points"). Else the pairs in order, each tried as soon as it passes.
    std::vector<std::pair<int, window::TwoViewResult>> candidates;
    bool done = false;
    for (int j = i + 1; j < run.n && j <= i + run.config.max_init_gap && !done; ++j) {
      window::TwoViewResult tv = window::InitializeTwoView(run.input.K, frames[i].points,
                                                           frames[j].points, run.config.two_view);
      if (!tv.ok) {
        *message = "frames " + std::to_string(i) + "-" + std::to_string(j) + ": " + tv.message;
        continue;
      }
      if (run.config.widest_init_pair)
        candidates.emplace_back(j, std::move(tv));
      else
        done = consider(j, tv);
    }
    for (auto c = candidates.rbegin(); c != candidates.rend() && !done; ++c)
      done = consider(c->first, c->second);
    if (!best) continue;
    const int j = best->start_frames.back();
    run.estimator = std::move(best->estimator);
    const std::vector<SE3d> start_poses = run.estimator->KeyframePoses();
    for (std::size_t k = 0; k < best->start_frames.size(); ++k) {
      const int f = best->start_frames[k];
      run.poses[f] = start_poses[k];
      run.has_pose[f] = true;
      run.status[f] = "initialization";
      run.keyframe[f] = true;
    }
    run.keyframes += static_cast<int>(best->start_frames.size());
    run.maps.push_back({{"frames", {i, j}},
                        {"keyframes", best->start_frames},
                        {"after_lost_frame", from > 0 ? from - 1 : -1},
                        {"scale", best->chained ? "chained" : "unit_baseline"},
                        {"baseline", best->chained ? *best->chained : 1.0},
                        {"points", best->init.points},
                        {"lines", best->init.lines},
                        {"tries", tries},
                        {"chi2_z", best->chi2_z}});
    run.init_ms += ThreadCpuMs() - t0;
    return std::make_pair(i, j);
  }
  run.init_ms += ThreadCpuMs() - t0;
  return std::nullopt;
}

// The frames from `from` up to the second view b (except a) against the new map: before a from
// a's pose, between a and b from the interpolation.
void LocalizeBeforeWindow(VoRun& run, int from, int a, int b) {
  for (int i = from; i < b; ++i) {
    if (run.status[i] == "initialization") continue;
    const SE3d guess = i < a
                           ? run.poses[a]
                           : Interpolate(run.poses[a], run.poses[b], double(i - a) / double(b - a));
    const std::optional<SE3d> T = run.estimator->Localize(run.input.frames[i], guess);
    run.poses[i] = T.value_or(guess);
    run.has_pose[i] = T.has_value();
    run.status[i] = T ? "localized_before_window" : "not_localized";
  }
}

nlohmann::json FrameJson(const window::FrameResult& r, const nlohmann::json& times) {
  return {{"keyframe", r.keyframe},
          {"tracked_points", r.tracked_points},
          {"tracked_lines", r.tracked_lines},
          {"pnp_fallback", r.pnp_fallback},
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
          {"dropped_point_observations", r.dropped_point_observations},
          {"dropped_line_observations", r.dropped_line_observations},
          {"held_line_observations", r.held_line_observations},
          {"dropped_retained_line_observations", r.dropped_retained_line_observations},
          {"retained_poses", r.retained_poses},
          {"prior_lines", r.prior_lines},
          {"prior_rank", r.prior_rank},
          {"marginalization_failed", r.marginalization_failed},
          {"ms", times}};
}

window::FrameInput WithGuess(window::FrameInput frame, const SE3d& T_w_c) {
  frame.T_w_c_guess = T_w_c;
  return frame;
}

// Per frame: window AddFrame (predict, track with the PnP fallback, keyframe, triangulate,
// solve, marginalize). Returns whether the frame was tracked.
bool TrackFrame(VoRun& run, int i, const std::optional<SE3d>& guess = std::nullopt) {
  BasicStageClock<window::WindowStage, window::kNumWindowStages> ms;
  const double t0 = ThreadCpuMs();
  const window::FrameResult r =
      guess ? run.estimator->AddFrame(WithGuess(run.input.frames[i], *guess), ms.Observer())
            : run.estimator->AddFrame(run.input.frames[i], ms.Observer());
  const double frame_ms = ThreadCpuMs() - t0;
  run.frame_total += frame_ms;
  ++run.window_frames;
  for (int s = 0; s < window::kNumWindowStages; ++s) run.stage_total[s] += ms.ms(s);
  const bool finite = r.T_w_c.translation().allFinite() && r.T_w_c.rotation().coeffs().allFinite();
  const bool ok = r.ok && finite;
  run.poses[i] = finite ? r.T_w_c : run.poses[std::max(i - 1, 0)];
  run.has_pose[i] = ok;
  run.status[i] = ok ? "tracked" : "lost";
  run.keyframe[i] = r.keyframe;
  run.keyframes += r.keyframe;
  run.lost += !ok;
  run.pnp_recoveries += r.pnp_fallback && ok;
  run.marginalized += r.marginalized_keyframes;
  run.failed_marginalizations += r.marginalization_failed;
  nlohmann::json times = {{"total", frame_ms}};
  for (int s = 0; s < window::kNumWindowStages; ++s) times[kStageNames[s]] = ms.ms(s);
  run.per_frame[i] = FrameJson(r, times);
  return ok;
}

// --draw: the frame's overlay (image input only; the observations are in the undistorted
// pinhole, so a --sensor image is undistorted again first).
void DrawFrame(const VoRun& run, int i) {
  if (run.args.draw.empty() || run.input.info[i].is_null() || !run.input.info[i].count("image"))
    return;
  const std::string path = run.input.info[i]["image"].get<std::string>();
  cv::Mat gray;
  try {
    gray = io::ReadGrayImage(path);
  } catch (const io::IoError&) {
    return;  // skipped image: already warned about
  }
  if (run.input.undistorter) gray = run.input.undistorter->Undistort(gray);
  const cv::Mat canvas = DrawVoFrame(gray, run.input.K, run.input.frames[i], run.poses[i],
                                     run.estimator->Points(), run.estimator->Lines());
  char name[32];
  std::snprintf(name, sizeof(name), "%06d.png", i);
  const std::string out = run.args.draw + "/" + name;
  if (!cv::imwrite(out, canvas)) throw io::IoError(out, "cannot write the overlay image");
}

void WriteJson(const VoRun& run, double read_ms, double total_ms) {
  nlohmann::json out;
  nlohmann::json list = nlohmann::json::array();
  for (int i = 0; i < run.n; ++i) {
    nlohmann::json f = run.per_frame[i].is_null() ? nlohmann::json::object() : run.per_frame[i];
    if (!run.input.info[i].is_null()) f["frontend"] = run.input.info[i];
    f["frame"] = i;
    f["time"] = run.input.frames[i].time;
    f["status"] = run.status[i];
    f["keyframe"] = static_cast<bool>(run.keyframe[i]);
    list.push_back(f);
  }
  const int wf = run.window_frames;
  nlohmann::json stages = nlohmann::json::object();
  for (int s = 0; s < window::kNumWindowStages; ++s)
    stages[kStageNames[s]] = wf > 0 ? run.stage_total[s] / wf : 0.0;
  out["frames"] = list;
  out["summary"] = {
      {"frames", run.n},
      {"initialization_frames", run.maps.front()["frames"]},
      {"maps", run.maps},
      {"reinitializations", static_cast<int>(run.maps.size()) - 1},
      {"keyframes", run.keyframes},
      {"lost_frames", run.lost},
      {"pnp_recoveries", run.pnp_recoveries},
      {"marginalized_keyframes", run.marginalized},
      {"failed_marginalizations", run.failed_marginalizations},
      {"use_lines", run.config.window.use_lines},
      {"keep_marginalized_lines", run.config.window.keep_marginalized_lines},
      {"retain_line_observer_poses", run.config.window.retain_line_observer_poses},
      {"max_retained_poses", run.config.window.max_retained_poses},
      {"retained_overflow_into_prior", run.config.window.retained_overflow_into_prior},
      {"prior_on_poses_only",
       run.config.window.prior_blocks == window::SlidingWindowOptions::PriorBlocks::kPoses},
      {"point_stride", run.args.point_stride},
      {"read_ms", read_ms},
      {"frontend_mean_ms", run.input.frontend_ms},
      {"skipped_images", run.input.warnings.size()},
      {"initialization_ms", run.init_ms},
      {"mean_frame_ms", wf > 0 ? run.frame_total / wf : 0.0},
      {"mean_stage_ms", stages},
      {"total_wall_ms", total_ms},
      {"frames_per_second_cpu", run.frame_total > 0 ? 1e3 * wf / run.frame_total : 0.0}};
  io::WriteFileAtomically(run.args.json, out.dump(1) + "\n");
}

// initialise, localise the frames before the window, then per frame the window; after
// max_lost_frames lost frames in a row a new map starts (re-initialisation) from the last one.
int Run(const VoArgs& a, const VoConfig& config_in) {
  // One thread: OpenCV's own pool (KLT, corners, RANSAC) off; Ceres runs with num_threads = 1.
  cv::setNumThreads(0);
  // The front end allocates MB-sized temporaries per image (corner responses, pyramids): served
  // by fresh mmaps, each page faults again every frame (measured: 40 ms of 48 in the points
  // stage of --no-lines on KITTI). Keep them on the heap.
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 128 << 20);
  const double t_start = WallMs();
  const VoInput input = ReadInput(a, config_in);
  VoConfig config = config_in;
  config.window.point_sigma_px = config.window.line_sigma_px = std::max(input.pixel_sigma, 0.5);
  VoRun run(a, config, input);
  if (run.n < 3)
    throw io::IoError(run.source, "needs at least 3 frames, has " + std::to_string(run.n));
  for (const std::string& w : input.warnings)
    std::cerr << "plucker vo: warning: skipped " << w << "\n";
  const double read_ms = WallMs() - t_start;
  if (!a.draw.empty()) std::filesystem::create_directories(a.draw);

  double last_progress = WallMs();
  int from = 0;
  while (from < run.n) {
    std::string message;
    const std::optional<std::pair<int, int>> ab = StartMap(run, from, &message);
    if (!ab) {
      if (run.maps.empty()) {
        throw io::IoError(
            a.features.empty() ? run.source : a.features,
            "cannot initialise (" + message + "): too few point tracks with parallax");
      }
      std::cerr << "plucker vo: warning: cannot re-initialise after frame " << from - 1 << " ("
                << message << "); the remaining frames keep the last pose\n";
      for (int i = from; i < run.n; ++i) run.poses[i] = run.poses[std::max(from - 1, 0)];
      break;
    }
    if (run.maps.size() > 1 && !a.quiet) {
      std::cerr << "\nplucker vo: re-initialised on frames " << ab->first << " and " << ab->second
                << "\n";
    }
    LocalizeBeforeWindow(run, from, ab->first, ab->second);
    for (int i = from; i <= ab->second; ++i) DrawFrame(run, i);
    from = run.n;
    int lost_in_a_row = 0;
    for (int i = ab->second + 1; i < run.n; ++i) {
      // The first frame after the start: constant velocity of the frame before b (the estimator's
      // own prediction would repeat the whole a-b motion).
      std::optional<SE3d> guess;
      const int b = ab->second;
      if (i == b + 1 && b - 1 > ab->first && run.has_pose[b - 1])
        guess = run.poses[b] * (run.poses[b - 1].Inverse() * run.poses[b]);
      lost_in_a_row = TrackFrame(run, i, guess) ? 0 : lost_in_a_row + 1;
      DrawFrame(run, i);
      const double now = WallMs();
      if (!a.quiet && (now - last_progress > 500.0 || i + 1 == run.n)) {
        last_progress = now;
        std::cerr << "\rplucker vo: frame " << (i + 1) << "/" << run.n << "  keyframes "
                  << run.keyframes << "  lost " << run.lost << "   " << std::flush;
      }
      if (lost_in_a_row >= a.max_lost_frames && i + 2 < run.n) {
        from = i + 1;
        break;
      }
    }
  }
  if (!a.quiet) std::cerr << "\n";
  io::WriteKittiPoses(a.out, run.poses);
  if (!a.json.empty()) WriteJson(run, read_ms, WallMs() - t_start);
  if (!a.quiet) {
    const auto& first = run.maps.front()["frames"];
    std::cerr << "plucker vo: " << run.n << " frames (initialised on frames " << first[0] << " and "
              << first[1] << "), " << run.keyframes << " keyframes, " << run.lost << " lost, "
              << run.maps.size() - 1 << " re-initialisations, " << std::fixed
              << std::setprecision(2)
              << (run.window_frames > 0 ? run.frame_total / run.window_frames : 0.0)
              << " ms CPU per frame; wrote " << a.out << "\n";
  }
  if (run.lost > 0) {
    std::cerr << "plucker vo: warning: " << run.lost
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
      return Run(*args, config);
    });
  });
}

}  // namespace app
}  // namespace plucker
