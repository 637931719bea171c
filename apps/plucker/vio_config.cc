#include "vio_config.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "vo_config.h"

namespace plucker {
namespace app {
namespace {

// "[a, b, ...]" of the values.
template <typename Values>
std::string FormatList(const Values& values, std::size_t n) {
  std::string s = "[";
  for (std::size_t i = 0; i < n; ++i)
    s += (i ? ", " : "") + options_internal::FormatNumber(values[i]);
  return s + "]";
}

// A YAML list of `size` finite numbers, or an empty one. std::invalid_argument otherwise: "expected
// a list of <size> numbers <shape>" for what is not a list of numbers, `invalid` for the wrong
// count or a value that is not finite.
std::vector<double> ReadFiniteList(const YAML::Node& n, std::size_t size, const std::string& shape,
                                   const std::string& invalid) {
  std::vector<double> e;
  try {
    if (!n.IsSequence()) throw std::invalid_argument("");
    e = n.as<std::vector<double>>();
  } catch (const std::exception&) {
    throw std::invalid_argument("expected a list of " + std::to_string(size) + " numbers " + shape);
  }
  const bool finite = std::all_of(e.begin(), e.end(), [](double v) { return std::isfinite(v); });
  if (!e.empty() && (e.size() != size || !finite)) throw std::invalid_argument(invalid);
  return e;
}

// [tx, ty, tz, qx, qy, qz, qw] with a non-zero quaternion, or empty.
OptionRow<VioConfig> ExtrinsicRow() {
  OptionRow<VioConfig> o{"extrinsic.T_b_c",
                         "list",
                         "m, quaternion",
                         "[tx, ty, tz, qx, qy, qz, qw]: the camera in the body frame instead of "
                         "the input's ([]: the input's)",
                         "7 finite numbers, quaternion != 0",
                         nullptr,
                         nullptr};
  o.get = [](const VioConfig& c) { return FormatList(c.T_b_c, c.T_b_c.size()); };
  o.set = [](const YAML::Node& n, VioConfig* c) {
    const std::string invalid =
        "expected 7 finite numbers [tx, ty, tz, qx, qy, qz, qw] with a non-zero quaternion";
    const std::vector<double> e = ReadFiniteList(n, 7, "[tx, ty, tz, qx, qy, qz, qw]", invalid);
    if (!e.empty() && Eigen::Vector4d(e[3], e[4], e[5], e[6]).norm() < 1e-6)
      throw std::invalid_argument(invalid);
    c->T_b_c = e;
  };
  return o;
}

// A 3-vector option of VisualInertialOdometryOptions ([x, y, z]), or empty (off).
using OptionalVector = std::optional<Eigen::Vector3d> odometry::VisualInertialOdometryOptions::*;
OptionRow<VioConfig> BiasRow(const char* key, const char* unit, const char* doc,
                             OptionalVector member) {
  OptionRow<VioConfig> o{key, "list", unit, doc, "3 finite numbers, or []", nullptr, nullptr};
  o.get = [member](const VioConfig& c) {
    const std::optional<Eigen::Vector3d>& v = c.odometry.*member;
    return FormatList(v.value_or(Eigen::Vector3d::Zero()), v ? 3 : 0);
  };
  o.set = [member](const YAML::Node& n, VioConfig* c) {
    const std::vector<double> e =
        ReadFiniteList(n, 3, "[x, y, z]", "expected 3 finite numbers [x, y, z] or []");
    std::optional<Eigen::Vector3d>& v = c->odometry.*member;
    v.reset();
    if (!e.empty()) v = Eigen::Vector3d(e[0], e[1], e[2]);
  };
  return o;
}

std::vector<OptionRow<VioConfig>> MakeRows() {
  OptionRows<VioConfig> t;
  t.Bool("use_lines", kUseLinesDoc, PLUCKER_OPTION_MEMBER(odometry.use_lines));
  t.Value(SharedVisualOption("window.size"), PLUCKER_OPTION_MEMBER(odometry.window));
  t.Value(SharedVisualOption("window.iterations"), PLUCKER_OPTION_MEMBER(odometry.iterations));
  t.Value(SharedVisualOption("window.keyframe_parallax_px"),
          PLUCKER_OPTION_MEMBER(odometry.keyframe_parallax_px));
  t.Value(SharedVisualOption("window.min_tracked"), PLUCKER_OPTION_MEMBER(odometry.min_tracked));
  t.Value(SharedVisualOption("window.min_tracked_ratio"),
          PLUCKER_OPTION_MEMBER(odometry.min_tracked_ratio));
  t.Value("window.keyframe_max_rotation_deg", "deg",
          "keyframe when the frame has turned this much from the newest one (0: off)", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(odometry.keyframe_max_rotation_deg));
  t.Value("window.keyframe_min_turn_rate_deg_s", "deg/s",
          "... only when some frame since the newest keyframe turned this fast from its previous "
          "frame (0: any rate; also the dynamic start's run)",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(odometry.keyframe_min_turn_rate_deg_s));
  t.Value(SharedVisualOption("window.min_line_views"),
          PLUCKER_OPTION_MEMBER(odometry.min_line_views));
  t.Value(SharedVisualOption("window.two_view_line_sigma_scale"),
          PLUCKER_OPTION_MEMBER(odometry.two_view_line_sigma_scale));
  t.Value(SharedVisualOption("window.two_view_min_plane_angle_px"),
          PLUCKER_OPTION_MEMBER(odometry.two_view_min_plane_angle_px));
  t.Bool("window.recheck_two_view_lines", kRecheckTwoViewLinesDoc,
         PLUCKER_OPTION_MEMBER(odometry.recheck_two_view_lines));
  t.Value("window.line_sigma_scale", "",
          "the line endpoint sigma: the pixel sigma times this (1: as the points)", Above(0.0),
          PLUCKER_OPTION_MEMBER(odometry.line_sigma_scale));
  t.Bool("window.keep_marginalized_lines",
         "keep k0's line information in the prior (false: dropped, as PL-VIO)",
         PLUCKER_OPTION_MEMBER(odometry.keep_marginalized_lines));
  t.Bool("window.prior_on_poses_only", kPriorOnPosesOnlyDoc,
         PLUCKER_OPTION_MEMBER(odometry.prior_on_poses_only));
  t.Value("inertial.max_imu_factor_span_s", "s",
          "a keyframe at the latest this long after the previous one (short IMU factors)",
          Above(0.0), PLUCKER_OPTION_MEMBER(odometry.max_imu_factor_span_s));
  t.Value("inertial.gyro_bias_prior_sigma", "rad/s", "prior on the first keyframe's gyro bias",
          Above(0.0), PLUCKER_OPTION_MEMBER(odometry.gyro_bias_prior_sigma));
  t.Value("inertial.accel_bias_prior_sigma", "m/s^2", "prior on the first keyframe's accel bias",
          Above(0.0), PLUCKER_OPTION_MEMBER(odometry.accel_bias_prior_sigma));
  t.Value("inertial.velocity_prior_sigma", "m/s", "prior on the first keyframe's velocity",
          Above(0.0), PLUCKER_OPTION_MEMBER(odometry.velocity_prior_sigma));
  t.Value("inertial.tracking_velocity_sigma", "m/s",
          "per-frame tracking fuses the IMU prediction with this sigma (0: vision only)",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(odometry.tracking_velocity_sigma));
  t.Value("init.min_keyframes", "keyframes", "dynamic start: keyframes before the alignment",
          AtLeast(4), PLUCKER_OPTION_MEMBER(odometry.init_min_keyframes));
  t.Value("init.max_keyframes", "keyframes",
          "dynamic start: the most it waits for (>= init.min_keyframes)", AtLeast(4),
          PLUCKER_OPTION_MEMBER(odometry.init_max_keyframes));
  t.Value("init.extend_keyframes", "keyframes",
          "dynamic start: after the first alignment, this many keyframes more, aligned again "
          "(0: off)",
          AtLeast(0), PLUCKER_OPTION_MEMBER(odometry.init_extend_keyframes));
  t.Value("init.extend_min_rotation_deg", "deg",
          "dynamic start: the extension waits until the body has turned this much from its "
          "first keyframe, then aligns again (0: off)",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(odometry.init_extend_min_rotation_deg));
  t.Value("init.extend_max_seconds", "s",
          "dynamic start: with init.extend_min_rotation_deg, the first alignment is kept when "
          "the turn has not come this long after it (0: no bound)",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(odometry.init_extend_max_seconds));
  t.Value("init.two_view_line_sigma_scale", "",
          "dynamic start: window.two_view_line_sigma_scale of its vision-only window (0: that)",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(odometry.init_two_view_line_sigma_scale));
  t.Value("init.min_span_s", "s",
          "dynamic start: the alignment waits until its keyframes span this long (0: off)",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(odometry.init_min_span_s));
  t.Value("init.keyframe_max_rotation_deg", "deg",
          "dynamic start: its vision-only run's keyframe also when the frame has turned this much, "
          "at window.keyframe_min_turn_rate_deg_s or faster (0: window.keyframe_max_rotation_deg)",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(odometry.init_keyframe_max_rotation_deg));
  t.Value("init.min_excitation", "m/s^2", "dynamic start: accelerometer excitation needed",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(odometry.init_min_excitation));
  t.Value("init.max_rotation_disagreement_deg", "deg",
          "two-view rotation against the gyroscope's, plus init.gyro_bias_bound x the time apart",
          Above(0.0), PLUCKER_OPTION_MEMBER(odometry.init_max_rotation_disagreement_deg));
  t.Value("init.gyro_bias_bound", "rad/s", "the largest gyro bias expected before it is known",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(odometry.init_gyro_bias_bound));
  t.Value("init.pair_budget", "pairs",
          "dynamic start: two-view RANSACs a frame of its search, the rest wait (0: no bound)",
          AtLeast(0), PLUCKER_OPTION_MEMBER(odometry.init_pair_budget));
  t.Value("init.pair_min_rotated_parallax_px", "px",
          "dynamic start: a pair's median point motion after the gyroscope's rotation needed "
          "before its RANSAC (0: not tested)",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(odometry.init_pair_min_rotated_parallax_px));
  t.Value("init.image_still_px", "px",
          "median point motion above which a frame moves (vetoes the static start)", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(odometry.image_still_px));
  t.Value("init.image_still_span_s", "s",
          "the static test's image motion: against the newest frame at least this much older",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(odometry.image_still_span_s));
  t.Value("init.ba_iterations", "iterations",
          "dynamic start: bundle adjustment over the alignment's keyframes (0: off)", AtLeast(0),
          PLUCKER_OPTION_MEMBER(odometry.init_ba_iterations));
  t.Value("init.ba_accel_bias_prior_sigma", "m/s^2",
          "its prior on the first keyframe's accel bias (weak)", Above(0.0),
          PLUCKER_OPTION_MEMBER(odometry.init_ba_accel_bias_prior_sigma));
  t.Value("init.ba_velocity_prior_sigma", "m/s", "its prior on the first keyframe's velocity",
          Above(0.0), PLUCKER_OPTION_MEMBER(odometry.init_ba_velocity_prior_sigma));
  t.Custom(BiasRow("init.accel_bias", "m/s^2",
                   "dynamic start: its bundle adjustment starts from (and centres its prior on) "
                   "this accel bias, [bx, by, bz] ([]: off; a diagnostic or an earlier run's)",
                   &odometry::VisualInertialOdometryOptions::init_accel_bias));
  t.Custom(BiasRow("init.gyro_bias", "rad/s",
                   "dynamic start: its bundle adjustment holds this gyro bias, [bx, by, bz] "
                   "([]: off; a diagnostic or an earlier run's)",
                   &odometry::VisualInertialOdometryOptions::init_gyro_bias));
  t.Value(SharedVisualOption("points.max_tracks"),
          PLUCKER_OPTION_MEMBER(odometry.max_point_tracks));
  t.Value(SharedVisualOption("points.min_distance_px"),
          PLUCKER_OPTION_MEMBER(odometry.point_min_distance_px));
  t.Value(SharedVisualOption("points.detect_below_share"),
          PLUCKER_OPTION_MEMBER(odometry.point_detect_below_share));
  t.Value(SharedVisualOption("lines.max_segments"),
          PLUCKER_OPTION_MEMBER(odometry.line_max_segments));
  t.Value(SharedVisualOption("lines.detection_scale"),
          PLUCKER_OPTION_MEMBER(odometry.line_detection_scale));
  t.Value(SharedVisualOption("lines.flow_samples"),
          PLUCKER_OPTION_MEMBER(odometry.line_flow_samples));
  t.Bool("extrinsic.estimate", "estimate T_b_c online (as --estimate-extrinsic)",
         PLUCKER_OPTION_MEMBER(odometry.estimate_extrinsic));
  t.Value("extrinsic.rotation_sigma", "rad", "prior on the given T_b_c's rotation", Above(0.0),
          PLUCKER_OPTION_MEMBER(odometry.extrinsic_rotation_sigma));
  t.Value("extrinsic.translation_sigma", "m", "prior on the given T_b_c's translation", Above(0.0),
          PLUCKER_OPTION_MEMBER(odometry.extrinsic_translation_sigma));
  t.Value("extrinsic.min_rotation_deg", "deg",
          "held until the window has rotated this much about two axes (0: free from the start)",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(odometry.extrinsic_min_rotation_deg));
  t.Custom(ExtrinsicRow());
  t.Bool("time_offset.estimate", "estimate the camera-IMU time offset (as --estimate-time-offset)",
         PLUCKER_OPTION_MEMBER(odometry.estimate_time_offset));
  t.Value("time_offset.initial_s", "s", "td, t_imu = t_cam + td (Kalibr's convention)",
          Range{-1.0, 1.0, true}, PLUCKER_OPTION_MEMBER(odometry.time_offset_s));
  t.Value("time_offset.prior_sigma_s", "s", "prior on td around time_offset.initial_s", Above(0.0),
          PLUCKER_OPTION_MEMBER(odometry.time_offset_prior_sigma_s));
  t.Value("input.point_stride", "",
          "features folders: the point tracks whose id is a multiple of this (as --point-stride)",
          AtLeast(1), PLUCKER_OPTION_MEMBER(point_stride));
  t.Value("checks.max_imu_only_share", "",
          "exit code 3 when more than this share of the frames had no visual update",
          Range{0.0, 1.0}, PLUCKER_OPTION_MEMBER(max_imu_only_share));
  t.Value("checks.max_keyframe_imu_chi2", "",
          "exit code 3 when a keyframe's IMU factor has a larger whitened squared residual (15 "
          "degrees of freedom): the IMU and the vision disagree (0: off)",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(max_keyframe_imu_chi2));
  t.Value("checks.max_start_imu_chi2", "",
          "exit code 3 when the window's first solve after the start leaves its newest IMU "
          "factor a larger whitened squared residual: a start on a wrong scale (0: off)",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(max_start_imu_chi2));
  t.Value("checks.max_start_culled_share", "",
          "exit code 3 when the window's first solve after the start culls more observations "
          "as outliers than this share of its residual blocks (from 10 on): a start on a wrong "
          "scale (0: off)",
          Range{0.0, 1.0}, PLUCKER_OPTION_MEMBER(max_start_culled_share));
  return t.Take();
}

}  // namespace

const OptionsTable<VioConfig>& VioOptions() {
  static const OptionsTable<VioConfig> table(
      TableText{"vio",
                "apps/plucker/vio_config.cc",
                {{"window", "the sliding window, window/sliding_window_estimator.h"},
                 {"inertial", "IMU factors and priors, window::InertialOptions"},
                 {"init", "static and dynamic initialisation, odometry/visual_inertial_odometry.h"},
                 {"points", "point tracks of --euroc images, vision/image_frontend.h"},
                 {"lines", "segments of --euroc images, vision/image_frontend.h"},
                 {"extrinsic", "online camera-body extrinsic (docs/vio.md)"},
                 {"time_offset", "online camera-IMU time offset (docs/vio.md)"},
                 {"input", "what plucker vio reads"},
                 {"checks", "when plucker vio fails (docs/cli.md, exit codes)"}},
                {{"window", "window.size"},
                 {"prior_on_poses_only", "window.prior_on_poses_only"},
                 {"iterations", "window.iterations"},
                 {"keyframe_parallax_px", "window.keyframe_parallax_px"},
                 {"min_tracked", "window.min_tracked"},
                 {"min_tracked_ratio", "window.min_tracked_ratio"},
                 {"keyframe_max_rotation_deg", "window.keyframe_max_rotation_deg"},
                 {"max_keyframe_interval_s", "inertial.max_imu_factor_span_s"},
                 {"gyro_bias_prior_sigma", "inertial.gyro_bias_prior_sigma"},
                 {"accel_bias_prior_sigma", "inertial.accel_bias_prior_sigma"},
                 {"velocity_prior_sigma", "inertial.velocity_prior_sigma"},
                 {"tracking_velocity_sigma", "inertial.tracking_velocity_sigma"},
                 {"init_min_keyframes", "init.min_keyframes"},
                 {"init_max_keyframes", "init.max_keyframes"},
                 {"init_min_excitation", "init.min_excitation"},
                 {"init_max_rotation_disagreement_deg", "init.max_rotation_disagreement_deg"},
                 {"init_gyro_bias_bound", "init.gyro_bias_bound"},
                 {"image_still_px", "init.image_still_px"},
                 {"image_still_span_s", "init.image_still_span_s"},
                 {"max_point_tracks", "points.max_tracks"},
                 {"point_min_distance_px", "points.min_distance_px"},
                 {"line_max_segments", "lines.max_segments"},
                 {"line_detection_scale", "lines.detection_scale"},
                 {"line_flow_samples", "lines.flow_samples"},
                 {"estimate_extrinsic", "extrinsic.estimate"},
                 {"extrinsic_rotation_sigma", "extrinsic.rotation_sigma"},
                 {"extrinsic_translation_sigma", "extrinsic.translation_sigma"},
                 {"extrinsic_min_rotation_deg", "extrinsic.min_rotation_deg"},
                 {"T_b_c", "extrinsic.T_b_c"},
                 {"estimate_time_offset", "time_offset.estimate"},
                 {"time_offset_s", "time_offset.initial_s"},
                 {"time_offset_prior_sigma_s", "time_offset.prior_sigma_s"},
                 {"point_stride", "input.point_stride"}}},
      MakeRows());
  return table;
}

void ApplyVioConfig(const std::string& path, VioConfig* config) { VioOptions().Load(path, config); }

void UseConfigExtrinsic(const VioConfig& config, SE3d* T_b_c) {
  const std::vector<double>& e = config.T_b_c;
  if (e.empty()) return;
  *T_b_c = SE3d(Eigen::Quaterniond(e[6], e[3], e[4], e[5]), Eigen::Vector3d(e[0], e[1], e[2]));
}

void ApplyVioConfigYaml(const std::string& text, const std::string& name, VioConfig* config) {
  VioOptions().Apply(text, name, config);
  CheckVioConfig(*config, name);
}

void CheckVioConfig(const VioConfig& config, const std::string& name) {
  const odometry::VisualInertialOdometryOptions& o = config.odometry;
  if (o.init_max_keyframes < o.init_min_keyframes) {
    throw std::runtime_error(
        name + ": key 'init.max_keyframes' (" + std::to_string(o.init_max_keyframes) +
        ") must be >= init.min_keyframes (" + std::to_string(o.init_min_keyframes) + ")");
  }
  const std::string problem = o.Problem();  // the library's own check, after the table's
  if (!problem.empty()) throw std::runtime_error(name + ": " + problem);
}

}  // namespace app
}  // namespace plucker
