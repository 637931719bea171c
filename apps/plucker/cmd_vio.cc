// plucker vio: monocular point + line visual-inertial odometry (docs/vio.md): the sliding window
// of `plucker vo` in its visual-inertial mode (window/sliding_window_estimator.h) on a features
// folder (docs/sim-format.md: rig.txt, imu.txt, points.txt, segments.txt) or a EuRoC folder (cam0
// images through the image front end, imu0). The pipeline reads as the algorithm:
//   initialise  static when the log starts still (gravity, gyro bias, accel bias along gravity;
//               inertial/static_initializer.h), else visual two-view SfM of the first keyframes
//               aligned with the preintegrated IMU (scale, gravity, velocities, gyro bias;
//               inertial/visual_inertial_alignment.h), chosen by inertial/initialization_choice;
//   per frame   window AddFrame: IMU prediction, visual tracking, keyframe decision,
//               triangulation, solve with the IMU factors, marginalization.
// Writes the TUM trajectory of the body (IMU) frame T_w_b in a gravity-aligned world for every
// frame that has a pose (frames before the initialisation included, marked in the JSON; a frame
// the IMU does not cover is skipped and recorded, never written with a made-up pose).
#include <yaml-cpp/yaml.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.h"
#include "plucker/eval/ate.h"
#include "plucker/eval/plot.h"
#include "plucker/inertial/initialization_choice.h"
#include "plucker/inertial/static_initializer.h"
#include "plucker/inertial/visual_inertial_alignment.h"
#include "plucker/io/io_error.h"
#include "plucker/io/trajectory_io.h"
#include "plucker/window/sliding_window_estimator.h"
#include "plucker/window/two_view_initialization.h"
#include "run_guarded.h"
#include "stage_clock.h"
#include "vio_input.h"

namespace plucker {
namespace app {
namespace {

// Every option of the command; --config FILE.yaml sets any of them by name.
struct VioConfig {
  bool use_lines = true;
  int point_stride = 1;
  int window = 10;
  // The poses-only prior (DSO pattern, the velocity and bias blocks and the IMU factor kept;
  // docs/vio.md); false: the prior on the landmarks of the marginalized keyframe (slower).
  bool prior_on_poses_only = true;
  // Keyframes and solver budget: the IMU bridges longer gaps between keyframes than VO needs.
  // On the room (60 s, seed 1) parallax 20 px, ratio 0.3 and 4 iterations took 152 keyframes of
  // 600: 0.037 m ATE at 2.4x real time (6.2x with --point-stride 2); VO's 10 px, 0.6 and 10
  // iterations took 297: 0.089 m at 0.7x.
  int iterations = 4;
  double keyframe_parallax_px = 20.0;
  int min_tracked = 20;            // a keyframe when fewer landmarks are tracked
  double min_tracked_ratio = 0.3;  // ... or fewer than this share of the frame's observations
  double max_keyframe_interval_s = 1.0;
  double gyro_bias_prior_sigma = 0.01;
  double accel_bias_prior_sigma = 0.1;
  double velocity_prior_sigma = 0.1;
  // Per-frame tracking fuses the IMU prediction (window::InertialOptions, m/s; 0: vision only).
  double tracking_velocity_sigma = 0.02;

  int init_min_keyframes = 10;        // dynamic initialisation: keyframes before the alignment
  int init_max_keyframes = 30;        // ... and the most it waits for
  double init_min_excitation = 0.25;  // m/s^2
  // The two-view start's rotation must agree with the gyroscope's (integrated at zero bias)
  // within this angle plus init_gyro_bias_bound times the time between the two frames.
  double init_max_rotation_disagreement_deg = 1.0;
  double init_gyro_bias_bound = 0.1;  // rad/s, the largest gyro bias expected before it is known
  // A frame whose median point displacement against the previous frame exceeds this moves
  // (vetoes the static initialisation over its IMU block).
  double image_still_px = 3.0;
  // EuRoC image front end: the speed settings of `plucker vo --images` (docs/vo.md).
  int max_point_tracks = 200;
  double point_min_distance_px = 20.0;
  int line_max_segments = 60;         // longest segments kept per image (0: all)
  double line_detection_scale = 0.5;  // image scale of the segment detection
  int line_flow_samples = 3;          // points per segment followed by optical flow
  // Online estimation of the camera-body extrinsic (window::InertialOptions, docs/vio.md), with
  // a prior on the given T_b_c (sigmas in rad and m); held until the window has rotated this much
  // about two axes (0: free from the start).
  bool estimate_extrinsic = false;
  double extrinsic_rotation_sigma = 0.05;
  double extrinsic_translation_sigma = 0.02;
  double extrinsic_min_rotation_deg = 0.0;
  // The T_b_c to use instead of the input's (rig.txt or sensor.yaml): [tx, ty, tz, qx, qy, qz,
  // qw], the camera in the body frame; empty: the input's.
  std::vector<double> T_b_c;
};

struct VioArgs {
  std::string features, euroc, out, json, plot, config;
  bool no_lines = false;
  bool quiet = false;
  bool estimate_extrinsic = false;
  int point_stride = 1, window = 10;
  VioConfig cfg;
};

const char* kStageNames[window::kNumWindowStages] = {"tracking", "triangulation", "solve",
                                                     "marginalization"};

using ConfigSetter = std::function<void(const YAML::Node&, VioConfig*)>;

template <typename T>
ConfigSetter Field(T VioConfig::*member) {
  return [member](const YAML::Node& node, VioConfig* c) { c->*member = node.as<T>(); };
}

// The keys of --config, one per VioConfig field.
const std::map<std::string, ConfigSetter>& ConfigFields() {
  static const std::map<std::string, ConfigSetter> fields = {
      {"use_lines", Field(&VioConfig::use_lines)},
      {"point_stride", Field(&VioConfig::point_stride)},
      {"window", Field(&VioConfig::window)},
      {"prior_on_poses_only", Field(&VioConfig::prior_on_poses_only)},
      {"iterations", Field(&VioConfig::iterations)},
      {"keyframe_parallax_px", Field(&VioConfig::keyframe_parallax_px)},
      {"min_tracked", Field(&VioConfig::min_tracked)},
      {"min_tracked_ratio", Field(&VioConfig::min_tracked_ratio)},
      {"max_keyframe_interval_s", Field(&VioConfig::max_keyframe_interval_s)},
      {"gyro_bias_prior_sigma", Field(&VioConfig::gyro_bias_prior_sigma)},
      {"accel_bias_prior_sigma", Field(&VioConfig::accel_bias_prior_sigma)},
      {"velocity_prior_sigma", Field(&VioConfig::velocity_prior_sigma)},
      {"tracking_velocity_sigma", Field(&VioConfig::tracking_velocity_sigma)},
      {"init_min_keyframes", Field(&VioConfig::init_min_keyframes)},
      {"init_max_keyframes", Field(&VioConfig::init_max_keyframes)},
      {"init_min_excitation", Field(&VioConfig::init_min_excitation)},
      {"init_max_rotation_disagreement_deg", Field(&VioConfig::init_max_rotation_disagreement_deg)},
      {"init_gyro_bias_bound", Field(&VioConfig::init_gyro_bias_bound)},
      {"image_still_px", Field(&VioConfig::image_still_px)},
      {"max_point_tracks", Field(&VioConfig::max_point_tracks)},
      {"point_min_distance_px", Field(&VioConfig::point_min_distance_px)},
      {"line_max_segments", Field(&VioConfig::line_max_segments)},
      {"line_detection_scale", Field(&VioConfig::line_detection_scale)},
      {"line_flow_samples", Field(&VioConfig::line_flow_samples)},
      {"estimate_extrinsic", Field(&VioConfig::estimate_extrinsic)},
      {"extrinsic_rotation_sigma", Field(&VioConfig::extrinsic_rotation_sigma)},
      {"extrinsic_translation_sigma", Field(&VioConfig::extrinsic_translation_sigma)},
      {"extrinsic_min_rotation_deg", Field(&VioConfig::extrinsic_min_rotation_deg)},
      {"T_b_c", Field(&VioConfig::T_b_c)},
  };
  return fields;
}

// Reads --config: a YAML map of VioConfig keys. Unknown keys and wrong types name the file.
void ApplyConfig(const std::string& path, VioConfig* c) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw io::IoError(path, "invalid YAML: " + e.msg);
  }
  if (root.IsNull()) return;
  if (!root.IsMap()) throw io::IoError(path, "expected a map of option: value");
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    const auto field = ConfigFields().find(key);
    if (field == ConfigFields().end()) throw io::IoError(path, "unknown option '" + key + "'");
    try {
      field->second(kv.second, c);
    } catch (const YAML::Exception&) {
      throw io::IoError(path, "option '" + key + "' has a value of the wrong type");
    }
  }
  if (c->point_stride < 1 || c->window < 2 || c->iterations < 1 || c->init_min_keyframes < 4 ||
      c->init_max_keyframes < c->init_min_keyframes || !(c->max_keyframe_interval_s > 0.0) ||
      !(c->gyro_bias_prior_sigma > 0.0) || !(c->accel_bias_prior_sigma > 0.0) ||
      !(c->velocity_prior_sigma > 0.0) || !(c->init_max_rotation_disagreement_deg > 0.0) ||
      !(c->init_gyro_bias_bound >= 0.0) || !(c->tracking_velocity_sigma >= 0.0) ||
      c->max_point_tracks < 1 || !(c->point_min_distance_px > 0.0) || c->line_max_segments < 0 ||
      !(c->line_detection_scale > 0.0 && c->line_detection_scale <= 1.0) ||
      c->line_flow_samples < 2) {
    throw io::IoError(
        path,
        "an option is out of range (point_stride >= 1, window >= 2, "
        "init_min_keyframes >= 4, sigmas and intervals > 0, tracking_velocity_sigma >= 0, "
        "0 < line_detection_scale <= 1, line_flow_samples >= 2)");
  }
  if (!(c->extrinsic_rotation_sigma > 0.0) || !(c->extrinsic_translation_sigma > 0.0) ||
      !(c->extrinsic_min_rotation_deg >= 0.0)) {
    throw io::IoError(path,
                      "extrinsic_rotation_sigma and extrinsic_translation_sigma must be > 0, "
                      "extrinsic_min_rotation_deg >= 0");
  }
  const std::vector<double>& e = c->T_b_c;
  const bool finite = std::all_of(e.begin(), e.end(), [](double v) { return std::isfinite(v); });
  if (!e.empty() &&
      (e.size() != 7 || !finite || Eigen::Vector4d(e[3], e[4], e[5], e[6]).norm() < 1e-6)) {
    throw io::IoError(path,
                      "T_b_c must be 7 finite numbers [tx, ty, tz, qx, qy, qz, qw] with a non-zero "
                      "quaternion");
  }
}

// The window's options from the configuration and the input's sensors.
window::SlidingWindowOptions WindowOptions(const VioConfig& c, const VioInput& in) {
  window::SlidingWindowOptions o;
  o.window_size = c.window;
  o.max_iterations = c.iterations;
  o.use_lines = c.use_lines;
  o.prior_blocks = c.prior_on_poses_only ? window::SlidingWindowOptions::PriorBlocks::kPoses
                                         : window::SlidingWindowOptions::PriorBlocks::kLandmarks;
  o.retire_marginalized_tracks = false;  // features folders: ids are scene ids, revisited
  o.keyframe_parallax_px = c.keyframe_parallax_px;
  o.min_tracked = c.min_tracked;
  o.min_tracked_ratio = c.min_tracked_ratio;
  o.point_sigma_px = o.line_sigma_px = std::max(in.pixel_sigma, 0.5);
  window::InertialOptions inertial;
  inertial.T_b_c = in.T_b_c;
  inertial.imu = in.imu_model;
  inertial.gravity_w = Eigen::Vector3d(0.0, 0.0, -in.gravity_magnitude);
  inertial.gyro_bias_prior_sigma = c.gyro_bias_prior_sigma;
  inertial.accel_bias_prior_sigma = c.accel_bias_prior_sigma;
  inertial.velocity_prior_sigma = c.velocity_prior_sigma;
  inertial.tracking_velocity_sigma = c.tracking_velocity_sigma;
  inertial.max_keyframe_interval_s = c.max_keyframe_interval_s;
  inertial.estimate_extrinsic = c.estimate_extrinsic;
  inertial.extrinsic_rotation_sigma = c.extrinsic_rotation_sigma;
  inertial.extrinsic_translation_sigma = c.extrinsic_translation_sigma;
  inertial.extrinsic_min_rotation_deg = c.extrinsic_min_rotation_deg;
  o.inertial = inertial;
  return o;
}

// The EuRoC image front end's options from the configuration.
vision::ImageFrontendOptions FrontendOptions(const VioConfig& c) {
  vision::ImageFrontendOptions o;
  o.use_lines = c.use_lines;
  o.points.target_count = c.max_point_tracks;
  o.points.min_distance_px = c.point_min_distance_px;
  o.max_segments = c.line_max_segments;
  o.detection_scale = c.line_detection_scale;
  o.lines.flow_samples = c.line_flow_samples;
  return o;
}

// The outcome of the initialisation: the window's first two keyframes and their states, the
// poses of the frames up to the second, and what happened (JSON events).
struct VioStart {
  std::string method;
  int first = -1, second = -1;
  window::InertialState state_first, state_second;
  // Earlier keyframes (dynamic), with their states: the window starts on the earliest of them
  // that shares enough landmarks with the second.
  std::vector<int> candidates;
  std::vector<window::InertialState> candidate_states;
  std::vector<std::optional<SE3d>> T_w_b;  // frames <= second
  nlohmann::json events = nlohmann::json::array();
};

bool Covered(const VioInput& in, double t) {
  return !in.imu.empty() && in.imu.front().t <= t && in.imu.back().t >= t;
}

// Static: the still span at the start of the log; the window starts on its first two frames.
bool StartStatic(const VioInput& in, const inertial::StaticInitResult& still, VioStart* s) {
  const int n = static_cast<int>(in.frames.size());
  int a = 0;
  while (a < n && (in.frames[a].time < still.still_begin || !Covered(in, in.frames[a].time))) ++a;
  if (a + 1 >= n || !Covered(in, in.frames[a + 1].time)) return false;
  s->method = "static";
  s->first = a;
  s->second = a + 1;
  window::InertialState st;
  st.T_w_b = SE3d(still.R_w_b, Eigen::Vector3d::Zero());
  st.bias = still.bias;
  s->state_first = s->state_second = st;
  s->T_w_b.assign(a + 2, std::nullopt);
  s->T_w_b[a] = s->T_w_b[a + 1] = st.T_w_b;
  return true;
}

// The metric pose of frame f from the visual pose, the alignment and keyframe 0's body pose.
SE3d AlignedBodyPose(const SE3d& T_vo_c0, const SE3d& T_vo_cf, double scale, const SE3d& T_w_b0,
                     const SE3d& T_b_c) {
  const SE3d rel = T_vo_c0.Inverse() * T_vo_cf;
  const SE3d scaled(rel.rotation(), scale * rel.translation());
  return T_w_b0 * T_b_c * scaled * T_b_c.Inverse();
}

// Dynamic: a vision-only window from a two-view start until min keyframes, then the alignment,
// retried with each new keyframe up to the maximum.
bool StartDynamic(const VioInput& in, const VioConfig& c, VioStart* s) {
  const int n = static_cast<int>(in.frames.size());
  window::SlidingWindowOptions vo = WindowOptions(c, in);
  vo.inertial.reset();
  vo.max_keyframe_interval_s = c.max_keyframe_interval_s;  // short IMU spans for the alignment
  vo.window_size = c.init_max_keyframes + 2;  // nothing is marginalized before the alignment
  for (int i = 0; i + 1 < n; ++i) {
    if (!Covered(in, in.frames[i].time)) continue;
    for (int j = i + 1; j < n && j <= i + 30; ++j) {
      if (!Covered(in, in.frames[j].time)) break;
      // The gyroscope's rotation between the two frames checks the visual start.
      const Eigen::Matrix3d R_bi_bj =
          PreintegrateSamples(in.imu, in.frames[i].time, in.frames[j].time, ImuBias(), in.imu_model)
              .DeltaR();
      const Eigen::Matrix3d R_b_c = in.T_b_c.RotationMatrix();
      const Eigen::Matrix3d R_cj_ci = R_b_c.transpose() * R_bi_bj.transpose() * R_b_c;
      window::TwoViewOptions two_view;
      two_view.max_rotation_disagreement_deg =
          c.init_max_rotation_disagreement_deg +
          c.init_gyro_bias_bound * (in.frames[j].time - in.frames[i].time) * 180.0 / M_PI;
      const window::TwoViewResult tv = window::InitializeTwoView(
          in.K, in.frames[i].points, in.frames[j].points, two_view, R_cj_ci);
      if (!tv.ok) continue;
      window::SlidingWindowEstimator estimator(in.K, vo);
      const window::InitializationResult init =
          estimator.Initialize(in.frames[i], SE3d(), in.frames[j], tv.T_b_a.Inverse());
      if (!init.ok) continue;
      std::vector<SE3d> T_vo(n);
      T_vo[i] = init.T_w_a;
      T_vo[j] = init.T_w_b;
      std::vector<int> keyframes = {i, j};
      for (int f = j + 1; f < n && static_cast<int>(keyframes.size()) <= c.init_max_keyframes;
           ++f) {
        if (!Covered(in, in.frames[f].time)) break;
        const window::FrameResult r = estimator.AddFrame(in.frames[f]);
        if (!r.ok) break;
        T_vo[f] = r.T_w_c;
        if (!r.keyframe) continue;
        keyframes.push_back(f);
        if (static_cast<int>(keyframes.size()) < c.init_min_keyframes) continue;
        inertial::AlignmentInput align;
        align.T_b_c = in.T_b_c;
        const std::vector<SE3d> kf = estimator.KeyframePoses();
        for (const SE3d& T : kf) align.T_c0_ck.push_back(kf.front().Inverse() * T);
        for (std::size_t k = 0; k + 1 < keyframes.size(); ++k) {
          align.preintegrations.push_back(PreintegrateSamples(in.imu, in.frames[keyframes[k]].time,
                                                              in.frames[keyframes[k + 1]].time,
                                                              ImuBias(), in.imu_model));
        }
        inertial::InitializationChoiceOptions choice_options;
        choice_options.min_keyframes = c.init_min_keyframes;
        choice_options.min_excitation = c.init_min_excitation;
        inertial::StaticInitResult not_still;
        not_still.status = inertial::StaticInitStatus::kNotStill;
        const inertial::InitializationChoice choice = inertial::ChooseInitialization(
            not_still, static_cast<int>(keyframes.size()),
            inertial::ImuExcitation(align.preintegrations), choice_options);
        if (choice.method != inertial::InitializationMethod::kDynamic) {
          s->events.push_back({{"frame", f}, {"event", "wait"}, {"reason", choice.reason}});
          continue;
        }
        inertial::AlignmentOptions ao;
        ao.gravity_magnitude = in.gravity_magnitude;
        const inertial::AlignmentResult a = inertial::AlignVisualInertial(align, ao);
        s->events.push_back({{"frame", f},
                             {"event", "alignment"},
                             {"keyframes", keyframes.size()},
                             {"status", inertial::ToString(a.status)},
                             {"message", a.message},
                             {"scale", a.scale}});
        if (!a.success()) continue;
        s->method = "dynamic";
        s->first = keyframes.front();
        s->second = keyframes.back();
        s->state_first = {a.T_w_bk.front(), a.velocities_w.front(), a.bias};
        s->state_second = {a.T_w_bk.back(), a.velocities_w.back(), a.bias};
        for (std::size_t k = 0; k + 1 < keyframes.size(); ++k) {
          s->candidates.push_back(keyframes[k]);
          s->candidate_states.push_back({a.T_w_bk[k], a.velocities_w[k], a.bias});
        }
        s->T_w_b.assign(f + 1, std::nullopt);
        for (int g = i; g <= f; ++g) {
          s->T_w_b[g] = AlignedBodyPose(T_vo[i], T_vo[g], a.scale, a.T_w_bk.front(), in.T_b_c);
        }
        return true;
      }
      s->events.push_back(
          {{"frame", i}, {"event", "restart"}, {"reason", "no alignment with this start"}});
      i = std::max(i, keyframes.size() > 2 ? keyframes[2] - 1 : j - 1);
      break;
    }
  }
  return false;
}

// Image motion of each frame against the previous one: the median displacement of the common
// point tracks (a smooth motion such as a constant turn leaves the IMU spread small; the images
// tell that the body moves). Frames without common tracks get no flag.
std::vector<inertial::ImageMotionFlag> ImageMotion(const VioInput& in, double still_px) {
  std::vector<inertial::ImageMotionFlag> flags;
  for (std::size_t i = 1; i < in.frames.size(); ++i) {
    std::map<int, Eigen::Vector2d> previous;
    for (const auto& p : in.frames[i - 1].points) previous[p.point_id] = p.uv;
    std::vector<double> d;
    for (const auto& p : in.frames[i].points) {
      const auto it = previous.find(p.point_id);
      if (it != previous.end()) d.push_back((p.uv - it->second).norm());
    }
    if (d.size() < 5) continue;
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    flags.push_back({in.frames[i].time, d[d.size() / 2] <= still_px});
  }
  return flags;
}

VioStart Start(const VioInput& in, const VioConfig& c) {
  VioStart s;
  inertial::StaticInitOptions so;
  so.gravity_magnitude = in.gravity_magnitude;
  const inertial::StaticInitResult still = inertial::InitializeStatic(
      in.imu, so, in.frames.front().time, ImageMotion(in, c.image_still_px));
  s.events.push_back({{"event", "static_test"},
                      {"status", inertial::ToString(still.status)},
                      {"message", still.message}});
  if (still.success() && StartStatic(in, still, &s)) {
    s.events.back()["still_seconds"] = still.still_end - still.still_begin;
    s.events.back()["gyro_bias"] = {still.bias.gyro.x(), still.bias.gyro.y(), still.bias.gyro.z()};
    s.events.back()["up_b"] = {still.up_b.x(), still.up_b.y(), still.up_b.z()};
    return s;
  }
  if (StartDynamic(in, c, &s)) return s;
  throw io::IoError(in.source,
                    "cannot initialise: the log does not start still and no visual-inertial "
                    "alignment succeeded (too little parallax or IMU excitation)");
}

nlohmann::json StateJson(const window::InertialState& s) {
  const Eigen::Vector3d& v = s.v_w;
  return {{"v_w", {v.x(), v.y(), v.z()}},
          {"gyro_bias", {s.bias.gyro.x(), s.bias.gyro.y(), s.bias.gyro.z()}},
          {"accel_bias", {s.bias.accel.x(), s.bias.accel.y(), s.bias.accel.z()}}};
}

bool Finite(const SE3d& T) {
  return T.translation().allFinite() && T.rotation().coeffs().allFinite();
}

// Top view of the estimate (and the ground truth when the input has it), position+yaw aligned.
void WritePlot(const std::string& path, const VioInput& in, const std::vector<int>& frames,
               const std::vector<SE3d>& T_w_b) {
  eval::TrajectoryPlot plot;
  plot.subtitle = in.source;
  std::vector<SE3d> est = T_w_b;
  if (in.gt_T_w_b) {
    std::vector<SE3d> gt;
    for (int f : frames) gt.push_back((*in.gt_T_w_b)[f]);
    const eval::AteResult ate = eval::ComputeAte(gt, T_w_b, {eval::AlignmentMode::kPositionYaw});
    est = ate.aligned_estimate;
    std::ostringstream title;
    title << "plucker vio: ATE (position+yaw aligned) RMSE " << std::setprecision(3)
          << ate.translation_m.rmse << " m over " << gt.size() << " poses";
    plot.title = title.str();
    for (const SE3d& T : gt) plot.positions_gt.push_back(T.translation());
    eval::PlotSeries series;
    series.label = "position error";
    for (std::size_t i = 0; i < gt.size(); ++i)
      series.points.emplace_back(in.frames[frames[i]].time, ate.translation_errors[i]);
    plot.error_series.push_back(series);
    plot.error_title = "position error over time";
    plot.error_x_label = "time [s]";
    plot.error_y_label = "position error [m]";
  } else {
    plot.title = "plucker vio: body trajectory (no ground truth)";
    plot.error_message = "no ground truth in the input";
  }
  for (const SE3d& T : est) plot.positions_est.push_back(T.translation());
  io::WriteFileAtomically(path, eval::RenderTrajectoryPlotSvg(plot));
}

// [tx, ty, tz, qx, qy, qz, qw]
nlohmann::json PoseJson(const SE3d& T) {
  const Eigen::Quaterniond& q = T.rotation();
  const Eigen::Vector3d& t = T.translation();
  return {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
}

// The extrinsic at the end (given, or estimated) and its change from the given one.
nlohmann::json ExtrinsicJson(const SE3d& given, const window::SlidingWindowEstimator& estimator,
                             bool estimated) {
  const SE3d T = estimator.ExtrinsicEstimate();
  return {{"estimated", estimated},
          {"freed", estimator.ExtrinsicFree()},
          {"T_b_c_given", PoseJson(given)},
          {"T_b_c", PoseJson(T)},
          {"rotation_change_deg",
           LogSO3<double>(given.rotation().conjugate() * T.rotation()).norm() * 180.0 / M_PI},
          {"translation_change_m", (T.translation() - given.translation()).norm()}};
}

int Run(const VioArgs& a) {
  const double t_start = WallMs();
  VioConfig cfg = a.cfg;
  if (a.no_lines) cfg.use_lines = false;
  VioInput in = a.euroc.empty() ? ReadVioFeatures(a.features, cfg.point_stride)
                                : ReadVioEuroc(a.euroc, FrontendOptions(cfg), a.quiet);
  // Frames without image motion: the window's zero-motion update (a standing body).
  const std::vector<inertial::ImageMotionFlag> motion = ImageMotion(in, cfg.image_still_px);
  for (std::size_t i = 1, k = 0; i < in.frames.size(); ++i) {
    while (k < motion.size() && motion[k].t < in.frames[i].time) ++k;
    in.frames[i].stationary =
        k < motion.size() && motion[k].t == in.frames[i].time && motion[k].still;
  }
  if (in.frames.size() > 1) in.frames[0].stationary = in.frames[1].stationary;
  const int n = static_cast<int>(in.frames.size());
  if (n < 3) throw io::IoError(in.source, "needs at least 3 frames, has " + std::to_string(n));
  for (const std::string& w : in.warnings) std::cerr << "plucker vio: warning: " << w << "\n";
  if (!cfg.T_b_c.empty()) {  // --config T_b_c: the extrinsic given instead of the input's
    const std::vector<double>& e = cfg.T_b_c;
    in.T_b_c = SE3d(Eigen::Quaterniond(e[6], e[3], e[4], e[5]), Eigen::Vector3d(e[0], e[1], e[2]));
  }
  const double read_ms = WallMs() - t_start;

  std::vector<std::optional<SE3d>> T_w_b(n);
  std::vector<nlohmann::json> per_frame(n, nlohmann::json::object());
  std::vector<std::string> status(n, "before_initialization");
  const double t_init = ThreadCpuMs();
  VioStart start = Start(in, cfg);
  window::SlidingWindowEstimator estimator(in.K, WindowOptions(cfg, in));
  estimator.AddImu(in.imu);
  // Dynamic: the window starts with the aligned keyframes (the newest `window` of them), else
  // (too few landmarks) with the earliest of them that shares enough landmarks with the newest.
  std::vector<int> start_keyframes;
  window::InitializationResult init;
  if (start.method == "dynamic") {
    std::vector<window::FrameInput> frames;
    std::vector<window::InertialState> states;
    const int first = std::max(0, static_cast<int>(start.candidates.size()) + 1 - cfg.window);
    for (int k = first; k < static_cast<int>(start.candidates.size()); ++k) {
      start_keyframes.push_back(start.candidates[k]);
      frames.push_back(in.frames[start.candidates[k]]);
      states.push_back(start.candidate_states[k]);
    }
    start_keyframes.push_back(start.second);
    frames.push_back(in.frames[start.second]);
    states.push_back(start.state_second);
    init = estimator.InitializeInertial(frames, states, 10);
    if (init.ok) start.first = start_keyframes.front();
  }
  if (!init.ok) {
    init = estimator.InitializeInertial(in.frames[start.first], start.state_first,
                                        in.frames[start.second], start.state_second,
                                        start.method == "static" ? 0 : 10);
  }
  for (std::size_t k = 1; !init.ok && k < start.candidates.size(); ++k) {
    start.first = start.candidates[k];
    start.state_first = start.candidate_states[k];
    init = estimator.InitializeInertial(in.frames[start.first], start.state_first,
                                        in.frames[start.second], start.state_second, 10);
  }
  if (!init.ok) {
    throw io::IoError(in.source, "the " + start.method +
                                     " initialisation succeeded but the window could not start "
                                     "(too few landmarks triangulated)");
  }
  const double init_ms = ThreadCpuMs() - t_init;
  // Frames up to the window's start: the initialisation's poses (the window's own for its two).
  for (int f = 0; f <= start.second && f < n; ++f) {
    if (f < static_cast<int>(start.T_w_b.size()) && start.T_w_b[f]) T_w_b[f] = start.T_w_b[f];
    status[f] = T_w_b[f] ? "initialization" : "before_initialization";
  }
  const std::vector<window::InertialState> first_states = estimator.KeyframeStates();
  if (first_states.size() != start_keyframes.size() || start_keyframes.front() != start.first)
    start_keyframes = {start.first, start.second};
  for (std::size_t k = 0; k < start_keyframes.size(); ++k) {
    T_w_b[start_keyframes[k]] = first_states[k].T_w_b;
    per_frame[start_keyframes[k]]["keyframe"] = true;
  }
  const SE3d T_c_b = in.T_b_c.Inverse();
  // Frames between the window's first keyframes: localized against its map (the aligned visual
  // poses carry the alignment's scale error), from the aligned pose of the frame.
  for (std::size_t k = 0; start.method == "dynamic" && k + 1 < start_keyframes.size(); ++k) {
    for (int f = start_keyframes[k] + 1; f < start_keyframes[k + 1]; ++f) {
      if (!T_w_b[f]) continue;
      const std::optional<SE3d> T_w_c = estimator.Localize(in.frames[f], *T_w_b[f] * in.T_b_c);
      if (T_w_c) T_w_b[f] = *T_w_c * T_c_b;
    }
  }
  // Frames before the initialisation without a pose: localized against the first map (motion-
  // only), else the first pose (the body taken as where it started).
  for (int f = start.first - 1; f >= 0; --f) {
    if (T_w_b[f]) continue;
    const SE3d& next = *T_w_b[f + 1];
    const std::optional<SE3d> T_w_c = estimator.Localize(in.frames[f], next * in.T_b_c);
    T_w_b[f] = T_w_c ? *T_w_c * T_c_b : next;
    if (T_w_c) status[f] = "localized_before_window";
  }

  int keyframes = 2, imu_only = 0, stationary = 0, skipped = 0, marginalized = 0,
      failed_marginalizations = 0;
  std::array<double, window::kNumWindowStages> stage_total{};
  double frame_total = 0.0, chi2_total = 0.0;
  double last_progress = WallMs();
  for (int i = start.second + 1; i < n; ++i) {
    BasicStageClock<window::WindowStage, window::kNumWindowStages> ms;
    const double t0 = ThreadCpuMs();
    window::FrameResult r;
    try {
      r = estimator.AddFrame(in.frames[i], ms.Observer());
    } catch (const std::invalid_argument& e) {  // the IMU does not cover the frame
      status[i] = "skipped_no_imu";
      per_frame[i]["reason"] = e.what();
      ++skipped;
      continue;
    }
    const double frame_ms = ThreadCpuMs() - t0;
    frame_total += frame_ms;
    for (int s = 0; s < window::kNumWindowStages; ++s) stage_total[s] += ms.ms(s);
    if (!Finite(r.state.T_w_b)) {
      status[i] = "skipped_non_finite";
      ++skipped;
      continue;
    }
    T_w_b[i] = r.state.T_w_b;
    status[i] = r.imu_only ? (r.stationary ? "stationary" : "imu_only") : "tracked";
    keyframes += r.keyframe;
    imu_only += r.imu_only && !r.stationary;
    stationary += r.stationary;
    marginalized += r.marginalized_keyframes;
    failed_marginalizations += r.marginalization_failed;
    chi2_total += r.imu_chi2;
    nlohmann::json times = {{"total", frame_ms}};
    for (int s = 0; s < window::kNumWindowStages; ++s) times[kStageNames[s]] = ms.ms(s);
    per_frame[i] = {{"keyframe", r.keyframe},
                    {"tracked_points", r.tracked_points},
                    {"tracked_lines", r.tracked_lines},
                    {"new_points", r.new_points},
                    {"new_lines", r.new_lines},
                    {"window_points", r.window_points},
                    {"window_lines", r.window_lines},
                    {"imu_chi2", r.imu_chi2},
                    {"tracking_iterations", r.tracking_iterations},
                    {"window_iterations", r.window_iterations},
                    {"marginalized_keyframes", r.marginalized_keyframes},
                    {"marginalization_failed", r.marginalization_failed},
                    {"state", StateJson(r.state)},
                    {"ms", times}};
    const double now = WallMs();
    if (!a.quiet && (now - last_progress > 500.0 || i + 1 == n)) {
      last_progress = now;
      std::cerr << "\rplucker vio: frame " << (i + 1) << "/" << n << "  keyframes " << keyframes
                << "  points " << r.window_points << "  lines " << r.window_lines << "   "
                << std::flush;
    }
  }
  if (!a.quiet) std::cerr << "\n";
  std::vector<double> times;
  std::vector<SE3d> poses;
  std::vector<int> written;
  for (int i = 0; i < n; ++i) {
    if (!T_w_b[i]) continue;
    times.push_back(in.frames[i].time);
    poses.push_back(*T_w_b[i]);
    written.push_back(i);
  }
  io::WriteTumTrajectory(a.out, times, poses);
  if (!a.plot.empty()) WritePlot(a.plot, in, written, poses);
  const int window_frames = n - start.second - 1 - skipped;
  const double duration = in.frames.back().time - in.frames.front().time;
  const double cpu_ms = init_ms + frame_total + in.frontend_cpu_ms;
  if (!a.json.empty()) {
    nlohmann::json list = nlohmann::json::array();
    for (int i = 0; i < n; ++i) {
      nlohmann::json f = per_frame[i];
      if (i < static_cast<int>(in.info.size()) && !in.info[i].is_null()) f["frontend"] = in.info[i];
      f["frame"] = i;
      f["time"] = in.frames[i].time;
      f["status"] = status[i];
      list.push_back(f);
    }
    nlohmann::json stages = nlohmann::json::object();
    for (int s = 0; s < window::kNumWindowStages; ++s)
      stages[kStageNames[s]] = window_frames > 0 ? stage_total[s] / window_frames : 0.0;
    nlohmann::json out;
    out["frames"] = list;
    out["initialization"] = {{"method", start.method},
                             {"frames", {start.first, start.second}},
                             {"events", start.events},
                             {"state_first", StateJson(start.state_first)}};
    out["summary"] = {
        {"frames", n},
        {"poses_written", poses.size()},
        {"keyframes", keyframes},
        {"imu_only_frames", imu_only},
        {"stationary_frames", stationary},
        {"skipped_frames", skipped},
        {"marginalized_keyframes", marginalized},
        {"failed_marginalizations", failed_marginalizations},
        {"mean_imu_chi2_keyframes", keyframes > 2 ? chi2_total / (keyframes - 2) : 0.0},
        {"use_lines", cfg.use_lines},
        {"point_stride", cfg.point_stride},
        {"read_ms", read_ms},
        {"frontend_cpu_ms", in.frontend_cpu_ms},
        {"frontend_mean_ms", in.frontend_ms},
        {"warnings", in.warnings},
        {"initialization_cpu_ms", init_ms},
        {"mean_frame_ms", window_frames > 0 ? frame_total / window_frames : 0.0},
        {"mean_stage_ms", stages},
        {"sequence_seconds", duration},
        {"cpu_seconds", cpu_ms / 1e3},
        {"times_real_time", cpu_ms > 0 ? 1e3 * duration / cpu_ms : 0.0},
        {"frames_per_second_cpu", cpu_ms > 0 ? 1e3 * n / cpu_ms : 0.0},
        {"total_wall_ms", WallMs() - t_start}};
    out["summary"]["extrinsic"] = ExtrinsicJson(in.T_b_c, estimator, cfg.estimate_extrinsic);
    io::WriteFileAtomically(a.json, out.dump(1) + "\n");
  }
  if (!a.quiet) {
    std::cerr << "plucker vio: " << n << " frames, " << start.method << " initialisation on frames "
              << start.first << "-" << start.second << ", " << keyframes << " keyframes, "
              << imu_only << " IMU-only, " << skipped << " skipped; " << std::fixed
              << std::setprecision(2) << cpu_ms / 1e3 << " s CPU for " << duration << " s of data ("
              << (cpu_ms > 0 ? 1e3 * duration / cpu_ms : 0.0) << "x real time); wrote " << a.out
              << "\n";
    if (cfg.estimate_extrinsic) {
      const SE3d T = estimator.ExtrinsicEstimate();
      std::cerr << "plucker vio: extrinsic " << (estimator.ExtrinsicFree() ? "estimated" : "held")
                << ": T_b_c moved " << std::setprecision(3)
                << LogSO3<double>(in.T_b_c.rotation().conjugate() * T.rotation()).norm() * 180.0 /
                       M_PI
                << " deg, " << std::setprecision(4)
                << (T.translation() - in.T_b_c.translation()).norm() << " m from the given one\n";
    }
  }
  if (skipped > 0) {
    std::cerr << "plucker vio: warning: " << skipped
              << " frames skipped (no IMU coverage or no finite pose; listed in the JSON)\n";
  }
  return 0;
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
  cmd->add_option("--out", args->out, "Output TUM trajectory of the body frame T_w_b")->required();
  cmd->add_option("--json", args->json, "Per-frame statistics, stage times and a summary (JSON)");
  cmd->add_option("--plot", args->plot, "SVG: top view (against the ground truth if present)");
  cmd->add_option(
         "--config", args->config,
         "YAML options (docs/vio.md): any of use_lines, point_stride, window, "
         "prior_on_poses_only, iterations, keyframe_parallax_px, min_tracked, min_tracked_ratio, "
         "max_keyframe_interval_s, gyro_bias_prior_sigma, accel_bias_prior_sigma, "
         "velocity_prior_sigma, tracking_velocity_sigma, init_min_keyframes, init_max_keyframes, "
         "init_min_excitation, init_max_rotation_disagreement_deg, init_gyro_bias_bound, "
         "image_still_px, max_point_tracks, point_min_distance_px, "
         "line_max_segments, line_detection_scale, line_flow_samples, estimate_extrinsic, "
         "extrinsic_rotation_sigma, extrinsic_translation_sigma, extrinsic_min_rotation_deg, "
         "T_b_c ([tx, ty, tz, qx, qy, qz, qw], instead of the input's)")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--no-lines", args->no_lines, "Points only");
  CLI::Option* estimate_extrinsic =
      cmd->add_flag("--estimate-extrinsic", args->estimate_extrinsic,
                    "Estimate the camera-body extrinsic T_b_c online (docs/vio.md)");
  CLI::Option* stride =
      cmd->add_option("--point-stride", args->point_stride,
                      "Use the point tracks whose id is a multiple of this (features folders)")
          ->check(CLI::Range(1, 1000000))
          ->capture_default_str();
  CLI::Option* window = cmd->add_option("--window", args->window, "Keyframes in the window")
                            ->check(CLI::Range(2, 1000))
                            ->capture_default_str();
  cmd->add_flag("--quiet", args->quiet, "No progress output (warnings are still printed)");
  cmd->callback([args, exit_code, stride, window, estimate_extrinsic]() {
    RunGuarded("vio", exit_code, [&] {
      if (args->features.empty() == args->euroc.empty()) {
        throw std::invalid_argument("give --features DIR or --euroc DIR");
      }
      // The configuration file, then what the command line gives explicitly.
      if (!args->config.empty()) ApplyConfig(args->config, &args->cfg);
      if (stride->count() > 0) args->cfg.point_stride = args->point_stride;
      if (window->count() > 0) args->cfg.window = args->window;
      if (estimate_extrinsic->count() > 0) args->cfg.estimate_extrinsic = true;
      return Run(*args);
    });
  });
}

}  // namespace app
}  // namespace plucker
