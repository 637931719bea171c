// `plucker eval init --euroc DIR`: visual-inertial initialisation against a EuRoC ground truth
// (inertial/, docs/math/vi-initialisation.md).
//   static:  the still period at the start of the log (InitializeStatic): gravity direction and
//            gyro bias against the ground truth over the span used;
//   dynamic: AlignVisualInertial on windows of keyframes along the whole flight, the camera poses
//            taken from the ground truth (T_w_b T_b_c, translations scaled by --visual-scale, as
//            an up-to-scale SfM would give them) and the real IMU between them: scale, gravity
//            direction and biases against the ground truth, and why windows fail.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "plucker/inertial/gravity.h"
#include "plucker/inertial/static_initializer.h"
#include "plucker/inertial/visual_inertial_alignment.h"
#include "plucker/io/camera_calibration.h"
#include "plucker/io/euroc_imu.h"
#include "run_guarded.h"

namespace plucker {
namespace app {
namespace {

constexpr double kDeg = M_PI / 180.0;

struct EvalInitArgs {
  std::string euroc;
  std::vector<double> accel_bias{0.0, 0.0, 0.0};
  int keyframes = 10;
  double keyframe_period = 0.2;
  double stride = 2.0;
  double visual_scale = 0.5;
  inertial::AlignmentOptions alignment;
  double noise_scale = 1.0;
  bool json = false;
};

Eigen::Vector3d UpB(const SE3d& T_w_b) { return T_w_b.RotationMatrix().transpose().col(2); }

// ---- static ----

struct StaticReport {
  inertial::StaticInitResult result;
  int gt_states = 0;
  Eigen::Vector3d gt_gyro_bias = Eigen::Vector3d::Zero(), gt_accel_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d gt_up = Eigen::Vector3d::UnitZ();
  double gyro_bias_error = 0.0, gravity_error_deg = 0.0, gt_horizontal_accel_bias = 0.0;
  // The ground truth's own consistency over the still span: the mean accelerometer reading
  // against the ground truth's up direction, raw and minus the ground truth's accel bias (0 if
  // its attitude and bias agreed), and how far its up direction wanders from its mean.
  double raw_accel_vs_gt_up_deg = 0.0, debiased_accel_vs_gt_up_deg = 0.0;
  double gt_up_wander_deg = 0.0;
};

StaticReport EvaluateStatic(const io::EurocImuRecording& rec, const Eigen::Vector3d& bias_prior) {
  StaticReport s;
  inertial::StaticInitOptions o;
  o.accel_bias_prior = bias_prior;
  s.result = inertial::InitializeStatic(rec.imu, o);
  if (!s.result.success()) return s;
  Eigen::Vector3d up = Eigen::Vector3d::Zero();
  for (const sensor::BodyState& b : rec.ground_truth) {
    if (b.t < s.result.still_begin || b.t >= s.result.still_end) continue;
    s.gt_gyro_bias += b.bias.gyro;
    s.gt_accel_bias += b.bias.accel;
    up += UpB(b.T_w_b);
    ++s.gt_states;
  }
  if (s.gt_states == 0) return s;
  s.gt_gyro_bias /= s.gt_states;
  s.gt_accel_bias /= s.gt_states;
  s.gt_up = up.normalized();
  s.gyro_bias_error = (s.result.bias.gyro - s.gt_gyro_bias).norm();
  s.gravity_error_deg = inertial::AngleBetween(s.result.up_b, s.gt_up) / kDeg;
  s.gt_horizontal_accel_bias = (s.gt_accel_bias - s.gt_accel_bias.dot(s.gt_up) * s.gt_up).norm();
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();
  int samples = 0;
  for (const sensor::ImuSample& m : rec.imu) {
    if (m.t < s.result.still_begin || m.t >= s.result.still_end) continue;
    accel += m.accel;
    ++samples;
  }
  accel /= std::max(samples, 1);
  s.raw_accel_vs_gt_up_deg = inertial::AngleBetween(accel, s.gt_up) / kDeg;
  s.debiased_accel_vs_gt_up_deg = inertial::AngleBetween(accel - s.gt_accel_bias, s.gt_up) / kDeg;
  for (const sensor::BodyState& b : rec.ground_truth) {
    if (b.t < s.result.still_begin || b.t >= s.result.still_end) continue;
    s.gt_up_wander_deg =
        std::max(s.gt_up_wander_deg, inertial::AngleBetween(UpB(b.T_w_b), s.gt_up) / kDeg);
  }
  return s;
}

// ---- dynamic ----

struct WindowError {
  double t0 = 0.0;
  double scale_error_pct = 0.0, gravity_error_deg = 0.0, gyro_bias_error = 0.0;
  double accel_bias_error = 0.0, velocity_error = 0.0, scale_sigma_pct = 0.0;
};

struct DynamicReport {
  int windows = 0;
  std::map<std::string, int> outcomes;
  std::vector<WindowError> errors;  // successful windows
  bool extrinsic_from_file = false;
};

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * (v.size() - 1) + 0.5))];
}

DynamicReport EvaluateDynamic(const io::EurocImuRecording& rec, const SE3d& T_b_c,
                              const EvalInitArgs& a) {
  DynamicReport d;
  const std::vector<sensor::BodyState>& gt = rec.ground_truth;
  if (gt.size() < 2) return d;
  const double gt_dt = (gt.back().t - gt.front().t) / static_cast<double>(gt.size() - 1);
  const int step = std::max(1, static_cast<int>(std::lround(a.keyframe_period / gt_dt)));
  const int stride = std::max(1, static_cast<int>(std::lround(a.stride / gt_dt)));
  for (std::size_t i0 = 0; i0 + static_cast<std::size_t>(step * (a.keyframes - 1)) < gt.size();
       i0 += stride) {
    inertial::AlignmentInput in;
    in.T_b_c = T_b_c;
    const SE3d T_w_c0 = gt[i0].T_w_b * T_b_c;
    Eigen::Vector3d gt_gyro = Eigen::Vector3d::Zero(), gt_accel = Eigen::Vector3d::Zero();
    std::vector<Eigen::Vector3d> v_c0;
    bool covered = true;
    for (int k = 0; k < a.keyframes; ++k) {
      const sensor::BodyState& b = gt[i0 + k * step];
      const SE3d T_c0_ck = T_w_c0.Inverse() * b.T_w_b * T_b_c;
      in.T_c0_ck.emplace_back(T_c0_ck.rotation(), a.visual_scale * T_c0_ck.translation());
      v_c0.push_back(T_w_c0.RotationMatrix().transpose() * b.v_w);
      gt_gyro += b.bias.gyro / a.keyframes;
      gt_accel += b.bias.accel / a.keyframes;
      if (k == 0) continue;
      try {
        in.preintegrations.push_back(PreintegrateSamples(rec.imu, gt[i0 + (k - 1) * step].t, b.t,
                                                         sensor::ImuBias{}, rec.imu_model));
      } catch (const std::invalid_argument&) {
        covered = false;
        break;
      }
    }
    if (!covered) continue;
    ++d.windows;
    const inertial::AlignmentResult r = inertial::AlignVisualInertial(in, a.alignment);
    ++d.outcomes[inertial::ToString(r.status)];
    if (!r.success()) continue;
    WindowError e;
    e.t0 = gt[i0].t;
    e.scale_error_pct = 100.0 * std::abs(r.scale * a.visual_scale - 1.0);
    e.scale_sigma_pct = 100.0 * r.scale_sigma / r.scale;
    const Eigen::Vector3d g_c0 = T_w_c0.RotationMatrix().transpose() * Eigen::Vector3d(0, 0, -1);
    e.gravity_error_deg = inertial::AngleBetween(r.gravity_c0, g_c0) / kDeg;
    e.gyro_bias_error = (r.bias.gyro - gt_gyro).norm();
    e.accel_bias_error = (r.bias.accel - gt_accel).norm();
    for (int k = 0; k < a.keyframes; ++k) {
      const Eigen::Vector3d v = r.R_w_c0.transpose() * r.states[k].v_w;
      e.velocity_error = std::max(e.velocity_error, (v - v_c0[k]).norm());
    }
    d.errors.push_back(e);
  }
  return d;
}

template <typename F>
std::vector<double> Column(const std::vector<WindowError>& errors, F f) {
  std::vector<double> v;
  for (const WindowError& e : errors) v.push_back(f(e));
  return v;
}

struct Row {
  const char* name;
  const char* unit;
  std::vector<double> values;
};

std::vector<Row> DynamicRows(const DynamicReport& d) {
  return {
      {"scale error", "%", Column(d.errors, [](auto& e) { return e.scale_error_pct; })},
      {"scale sigma", "%", Column(d.errors, [](auto& e) { return e.scale_sigma_pct; })},
      {"gravity direction", "deg", Column(d.errors, [](auto& e) { return e.gravity_error_deg; })},
      {"gyro bias", "rad/s", Column(d.errors, [](auto& e) { return e.gyro_bias_error; })},
      {"accel bias", "m/s^2", Column(d.errors, [](auto& e) { return e.accel_bias_error; })},
      {"velocity (max)", "m/s", Column(d.errors, [](auto& e) { return e.velocity_error; })}};
}

void PrintStatic(const StaticReport& s) {
  const inertial::StaticInitResult& r = s.result;
  std::printf("static initialisation: %s%s%s\n", inertial::ToString(r.status),
              r.message.empty() ? "" : ": ", r.message.c_str());
  if (!r.success()) return;
  std::printf(
      "  still span %.2f s (%d blocks still), %d samples; spread gyro %.3f rad/s, "
      "accel %.3f m/s^2\n",
      r.still_end - r.still_begin, r.blocks_still, r.samples_used, r.gyro_std.norm(),
      r.accel_std.norm());
  std::printf(
      "  gyro bias     %9.5f %9.5f %9.5f rad/s (ground truth %9.5f %9.5f %9.5f): error "
      "%.2e rad/s\n",
      r.bias.gyro.x(), r.bias.gyro.y(), r.bias.gyro.z(), s.gt_gyro_bias.x(), s.gt_gyro_bias.y(),
      s.gt_gyro_bias.z(), s.gyro_bias_error);
  std::printf(
      "  gravity direction error %.3f deg (estimated sigma %.3f deg); the ground truth's "
      "horizontal accel bias %.4f m/s^2 alone tilts by %.3f deg (not observable at rest)\n",
      s.gravity_error_deg, r.tilt_sigma / kDeg, s.gt_horizontal_accel_bias,
      s.gt_horizontal_accel_bias / 9.81 / kDeg);
  std::printf("  accel bias along gravity %.4f m/s^2 (ground truth %.4f)\n",
              r.bias.accel.dot(r.up_b), s.gt_accel_bias.dot(s.gt_up));
  std::printf(
      "  ground truth consistency: the mean accelerometer is %.3f deg from the ground truth's up "
      "direction, %.3f deg after subtracting the ground truth's accel bias (0 if its attitude "
      "and bias agreed); its up direction wanders %.3f deg from its mean over the still span\n",
      s.raw_accel_vs_gt_up_deg, s.debiased_accel_vs_gt_up_deg, s.gt_up_wander_deg);
}

void PrintDynamic(const DynamicReport& d, const EvalInitArgs& a) {
  std::printf(
      "dynamic initialisation: %d windows of %d keyframes every %.2f s (poses from the "
      "ground truth, extrinsic %s), real IMU\n",
      d.windows, a.keyframes, a.keyframe_period,
      d.extrinsic_from_file ? "from cam0/sensor.yaml" : "identity");
  std::printf("  outcomes:");
  for (const auto& [name, count] : d.outcomes) std::printf(" %s %d;", name.c_str(), count);
  if (d.errors.empty()) {
    std::printf("\n  no window aligned: no errors to report\n");
    return;
  }
  std::printf("\n  %-18s %6s %10s %10s %10s\n", "error", "unit", "median", "p95", "max");
  for (const Row& row : DynamicRows(d)) {
    std::printf("  %-18s %6s %10.4f %10.4f %10.4f\n", row.name, row.unit,
                Percentile(row.values, 0.5), Percentile(row.values, 0.95),
                Percentile(row.values, 1.0));
  }
}

nlohmann::json StaticJson(const StaticReport& s) {
  const inertial::StaticInitResult& r = s.result;
  nlohmann::json j = {{"status", inertial::ToString(r.status)}, {"message", r.message}};
  if (!r.success()) return j;
  j["still_seconds"] = r.still_end - r.still_begin;
  j["samples_used"] = r.samples_used;
  j["gyro_bias"] = {r.bias.gyro.x(), r.bias.gyro.y(), r.bias.gyro.z()};
  j["gyro_bias_error_radps"] = s.gyro_bias_error;
  j["gravity_direction_error_deg"] = s.gravity_error_deg;
  j["tilt_sigma_deg"] = r.tilt_sigma / kDeg;
  j["gt_horizontal_accel_bias_mps2"] = s.gt_horizontal_accel_bias;
  j["accel_bias_along_gravity_mps2"] = r.bias.accel.dot(r.up_b);
  j["gt_accel_bias_along_gravity_mps2"] = s.gt_accel_bias.dot(s.gt_up);
  j["raw_accel_vs_gt_up_deg"] = s.raw_accel_vs_gt_up_deg;
  j["debiased_accel_vs_gt_up_deg"] = s.debiased_accel_vs_gt_up_deg;
  j["gt_up_wander_deg"] = s.gt_up_wander_deg;
  return j;
}

nlohmann::json DynamicJson(const DynamicReport& d) {
  nlohmann::json j = {{"windows", d.windows}, {"outcomes", d.outcomes}};
  if (d.errors.empty()) return j;
  for (const Row& row : DynamicRows(d)) {
    j["errors"][row.name] = {{"unit", row.unit},
                             {"median", Percentile(row.values, 0.5)},
                             {"p95", Percentile(row.values, 0.95)},
                             {"max", Percentile(row.values, 1.0)}};
  }
  return j;
}

void Run(const EvalInitArgs& a) {
  io::EurocImuRecording rec = io::ReadEurocImuRecording(a.euroc);
  sensor::ImuModel& m = rec.imu_model;
  m.gyro_noise_density *= a.noise_scale;
  m.accel_noise_density *= a.noise_scale;
  m.gyro_bias_random_walk *= a.noise_scale;
  m.accel_bias_random_walk *= a.noise_scale;
  if (rec.ground_truth.empty()) {
    throw std::runtime_error(a.euroc + ": no mav0/state_groundtruth_estimate0/data.csv");
  }
  const StaticReport s =
      EvaluateStatic(rec, Eigen::Vector3d(a.accel_bias[0], a.accel_bias[1], a.accel_bias[2]));
  SE3d T_b_c;
  bool from_file = false;
  for (const std::string& path :
       {a.euroc + "/mav0/cam0/sensor.yaml", a.euroc + "/cam0/sensor.yaml"}) {
    if (std::ifstream(path)) {
      T_b_c = io::ReadEurocCamera(path).T_b_c;
      from_file = true;
      break;
    }
  }
  DynamicReport d = EvaluateDynamic(rec, T_b_c, a);
  d.extrinsic_from_file = from_file;
  if (a.json) {
    std::cout << nlohmann::json{{"static", StaticJson(s)}, {"dynamic", DynamicJson(d)}}.dump(2)
              << "\n";
  } else {
    PrintStatic(s);
    PrintDynamic(d, a);
  }
}

}  // namespace

void AddEvalInit(CLI::App* eval_cmd, int* exit_code) {
  auto a = std::make_shared<EvalInitArgs>();
  CLI::App* cmd = eval_cmd->add_subcommand(
      "init", "Visual-inertial initialisation (static and dynamic) against a EuRoC ground truth");
  cmd->add_option("--euroc", a->euroc, "EuRoC folder (with mav0/imu0 and ground truth)")
      ->required();
  cmd->add_option("--accel-bias", a->accel_bias,
                  "Known accelerometer bias (prior of the static initialisation) [m/s^2]")
      ->delimiter(',')
      ->expected(3);
  cmd->add_option("--keyframes", a->keyframes, "Keyframes per dynamic window")
      ->check(CLI::Range(4, 1000))
      ->capture_default_str();
  cmd->add_option("--keyframe-period", a->keyframe_period, "Time between keyframes [s]")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--stride", a->stride, "Time between the starts of dynamic windows [s]")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--visual-scale", a->visual_scale,
                  "Scale applied to the ground-truth translations (the alignment must find its "
                  "inverse)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--noise-scale", a->noise_scale,
                  "Dynamic: multiply every noise figure of sensor.yaml by this factor (the "
                  "preintegration covariances weigh the alignment)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--accel-bias-sigma", a->alignment.accel_bias_prior_sigma,
                  "Dynamic: prior sigma of the accelerometer bias (0 holds it at zero) [m/s^2]")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--visual-sigma", a->alignment.visual_position_sigma,
                  "Dynamic: noise of the metric keyframe positions [m]")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--max-scale-sigma", a->alignment.max_scale_relative_sigma,
                  "Dynamic: largest relative scale standard deviation accepted")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("--json", a->json, "Print machine-readable JSON instead of a table");
  cmd->callback([a, exit_code] { RunGuarded("eval init", exit_code, [&] { Run(*a); }); });
}

}  // namespace app
}  // namespace plucker
