#include "vio_output.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "pipeline_json.h"
#include "plucker/eval/ate.h"
#include "plucker/eval/plot.h"
#include "plucker/eval/statistics.h"
#include "plucker/io/io_error.h"
#include "plucker/io/trajectory_io.h"

namespace plucker {
namespace app {
namespace {

// [tx, ty, tz, qx, qy, qz, qw]
nlohmann::json PoseJson(const SE3d& T) {
  const Eigen::Quaterniond& q = T.rotation();
  const Eigen::Vector3d& t = T.translation();
  return {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
}

double AngleDeg(const SE3d& a, const SE3d& b) {
  return LogSO3<double>(a.rotation().conjugate() * b.rotation()).norm() * 180.0 / M_PI;
}

nlohmann::json EventJson(const odometry::VioInitEvent& e) {
  nlohmann::json j = {{"event", e.event}};
  if (e.frame >= 0) j["frame"] = e.frame;
  if (e.event == "static_test" || e.event == "alignment") {
    j["status"] = e.status;
    j["message"] = e.message;
  }
  if (!e.reason.empty()) j["reason"] = e.reason;
  if (e.event == "extension") j["keyframes"] = e.keyframes;
  if (e.event == "alignment") {
    j["keyframes"] = e.keyframes;
    j["scale"] = e.scale;
  }
  if (e.still) {
    j["still_seconds"] = e.still_seconds;
    j["gyro_bias"] = Vec3Json(e.gyro_bias);
    j["up_b"] = Vec3Json(e.up_b);
  }
  return j;
}

// Each call's odometry CPU time (a call per frame, the last one at the end of the input):
// median, p95, max and the call with the max.
nlohmann::json CallCpuJson(const std::vector<double>& ms) {
  if (ms.empty()) return nlohmann::json::object();
  const auto most = std::max_element(ms.begin(), ms.end());
  return {{"calls", ms.size()},
          {"median", eval::Percentile(ms, 0.5)},
          {"p95", eval::Percentile(ms, 0.95)},
          {"max", *most},
          {"max_call", most - ms.begin()}};
}

}  // namespace

void VioReport::AddFrontend(int frame, nlohmann::json info) {
  if (static_cast<int>(frontend_.size()) <= frame) frontend_.resize(frame + 1);
  frontend_[frame] = std::move(info);
}

void VioReport::Add(const odometry::VioFrameResult& r,
                    const std::array<double, window::kNumWindowStages>& window_ms,
                    double cpu_ms_call, double frontend_ms_call) {
  ++frames;
  cpu_ms += cpu_ms_call;
  frontend_ms += frontend_ms_call;
  const double odometry_ms = cpu_ms_call - frontend_ms_call;
  call_ms_.push_back(odometry_ms);
  const bool own = r.settled.size() == 1 && r.window;  // the window ran this frame alone
  if (own) {
    frame_ms += odometry_ms;
    ++window_frames_;
    for (int s = 0; s < window::kNumWindowStages; ++s) stage_total_[s] += window_ms[s];
  } else if (r.settled.size() != 1) {
    init_ms += odometry_ms;
  }
  for (const odometry::VioFrameRecord& rec : r.settled) {
    if (static_cast<int>(per_frame_.size()) <= rec.frame) {
      per_frame_.resize(rec.frame + 1, nlohmann::json::object());
      times_.resize(rec.frame + 1);
    }
    nlohmann::json& f = per_frame_[rec.frame];
    times_[rec.frame] = rec.time;
    f = nlohmann::json::object();
    if (rec.keyframe) f["keyframe"] = true;
    if (rec.status == odometry::VioStatus::kSkippedNoImu) f["reason"] = rec.skip_reason;
    skipped += rec.status == odometry::VioStatus::kSkippedNoImu ||
               rec.status == odometry::VioStatus::kSkippedNonFinite;
    f["status"] = odometry::ToString(rec);
    if (!rec.window) continue;
    const window::WindowFrameResult& w = *rec.window;
    const nlohmann::json stats = WindowFrameJson(w, true);
    for (auto& kv : stats.items()) f[kv.key()] = kv.value();
    keyframes += w.keyframe;
    imu_only += w.imu_only && !w.stationary;
    stationary += w.stationary;
    marginalized_ += w.marginalized_keyframes;
    failed_marginalizations_ += w.marginalization_failed;
    chi2_total_ += w.imu_chi2;
    if (w.keyframe) {
      keyframe_chi2.push_back(
          {rec.frame, rec.time, w.imu_chi2, w.culled_observations, w.residuals});
    }
    window_points = w.window_points;
    window_lines = w.window_lines;
    if (own) {
      nlohmann::json times = {{"total", odometry_ms}};
      for (int s = 0; s < window::kNumWindowStages; ++s) times[kWindowStageNames[s]] = window_ms[s];
      f["ms"] = times;
    }
  }
}

nlohmann::json VioReport::Json(const VioInput& in, const odometry::VisualInertialOdometry& vio,
                               double read_ms, double total_wall_ms) const {
  nlohmann::json list = nlohmann::json::array();
  nlohmann::json frontend_mean = nlohmann::json::object();
  for (std::size_t i = 0; i < per_frame_.size(); ++i) {
    nlohmann::json f = per_frame_[i];
    if (i < frontend_.size() && !frontend_[i].is_null()) {
      f["frontend"] = frontend_[i];
      for (auto& kv : frontend_[i]["ms"].items())
        frontend_mean[kv.key()] = frontend_mean.value(kv.key(), 0.0) +
                                  kv.value().get<double>() / static_cast<double>(frames);
    }
    f["frame"] = i;
    f["time"] = times_[i];
    list.push_back(f);
  }
  nlohmann::json stages = nlohmann::json::object();
  for (int s = 0; s < window::kNumWindowStages; ++s)
    stages[kWindowStageNames[s]] = window_frames_ > 0 ? stage_total_[s] / window_frames_ : 0.0;
  const odometry::VioInitialization& init = vio.initialization();
  nlohmann::json events = nlohmann::json::array();
  for (const odometry::VioInitEvent& e : init.events) events.push_back(EventJson(e));
  nlohmann::json out;
  out["frames"] = list;
  out["initialization"] = {{"method", init.method},
                           {"frames", {init.first, init.second}},
                           {"events", events},
                           {"state_first", InertialStateJson(init.state_first)}};
  if (init.adjustment.ran) {
    const odometry::StartAdjustmentSummary& a = init.adjustment;
    out["initialization"]["bundle_adjustment"] = {{"ok", a.ok},
                                                  {"keyframes", a.keyframes},
                                                  {"points", a.points},
                                                  {"lines", a.lines},
                                                  {"iterations", a.iterations},
                                                  {"final_cost", a.final_cost},
                                                  {"tilt_change_deg", a.tilt_change_deg},
                                                  {"scale_change", a.scale_change}};
  }
  const double duration = times_.empty() ? 0.0 : times_.back() - times_.front();
  const int poses = static_cast<int>(
      std::count_if(vio.RefinedTrajectory().begin(), vio.RefinedTrajectory().end(),
                    [](const odometry::VioFrameRecord& r) { return r.T_w_b.has_value(); }));
  out["summary"] = {
      {"frames", frames},
      {"poses_written", poses},
      {"keyframes", keyframes},
      {"imu_only_frames", imu_only},
      {"stationary_frames", stationary},
      {"skipped_frames", skipped},
      {"skipped_images", skipped_images},
      {"skipped_input_frames", in.skipped_input_frames},
      {"marginalized_keyframes", marginalized_},
      {"failed_marginalizations", failed_marginalizations_},
      {"mean_imu_chi2_keyframes", keyframes > 2 ? chi2_total_ / (keyframes - 2) : 0.0},
      {"read_ms", read_ms},
      {"frontend_cpu_ms", frontend_ms},
      {"frontend_mean_ms", frontend_mean},
      {"warnings", in.warnings},
      {"initialization_cpu_ms", init_ms},
      {"mean_frame_ms", window_frames_ > 0 ? frame_ms / window_frames_ : 0.0},
      {"mean_stage_ms", stages},
      {"sequence_seconds", duration},
      {"cpu_seconds", cpu_ms / 1e3},
      {"times_real_time", cpu_ms > 0 ? 1e3 * duration / cpu_ms : 0.0},
      {"frames_per_second_cpu", cpu_ms > 0 ? 1e3 * frames / cpu_ms : 0.0},
      {"total_wall_ms", total_wall_ms}};
  const SE3d& given = in.calibration.T_b_c;
  const SE3d T = vio.ExtrinsicEstimate();
  out["summary"]["extrinsic"] = {
      {"estimated", extrinsic_estimated},
      {"freed", vio.ExtrinsicFree()},
      {"T_b_c_given", PoseJson(given)},
      {"T_b_c", PoseJson(T)},
      {"rotation_change_deg", AngleDeg(given, T)},
      {"translation_change_m", (T.translation() - given.translation()).norm()}};
  const odometry::VioStatistics& st = vio.statistics();
  nlohmann::json stretches = nlohmann::json::array();
  for (const odometry::VioImuOnlyStretch& s : st.imu_only_stretches)
    stretches.push_back({{"frames", {s.first, s.last}}, {"seconds", {s.t_first, s.t_last}}});
  out["summary"]["imu_only_share"] = st.ImuOnlyShare();
  out["summary"]["imu_only_stretches"] = stretches;
  // Kalibr's convention: t_imu = t_cam + offset (IMU stamps 8 ms late read +0.008).
  out["summary"]["camera_imu_time_offset_s"] = vio.TimeOffsetEstimate();
  out["odometry_call_cpu_ms"] = CallCpuJson(call_ms_);
  return out;
}

void PrintVioSummary(const std::string& out, bool estimate_extrinsic, const VioReport& report,
                     const odometry::VisualInertialOdometry& vio, const VioInput& in,
                     double duration) {
  const odometry::VioInitialization& init = vio.initialization();
  const double cpu = report.cpu_ms;
  std::cerr << "plucker vio: " << report.frames << " frames, " << init.method
            << " initialisation on frames " << init.first << "-" << init.second << ", "
            << report.keyframes << " keyframes, " << report.imu_only << " IMU-only, "
            << report.skipped + report.skipped_images << " skipped; " << std::fixed
            << std::setprecision(2) << cpu / 1e3 << " s CPU for " << duration << " s of data ("
            << (cpu > 0 ? 1e3 * duration / cpu : 0.0) << "x real time); wrote " << out << "\n";
  if (!estimate_extrinsic) return;
  const SE3d T = vio.ExtrinsicEstimate();
  const SE3d& given = in.calibration.T_b_c;
  std::cerr << "plucker vio: extrinsic " << (vio.ExtrinsicFree() ? "estimated" : "held")
            << ": T_b_c moved " << std::setprecision(3)
            << LogSO3<double>(given.rotation().conjugate() * T.rotation()).norm() * 180.0 / M_PI
            << " deg, " << std::setprecision(4) << (T.translation() - given.translation()).norm()
            << " m from the given one\n";
}

int WarnImuOnly(const odometry::VioStatistics& stats, double max_share) {
  std::vector<const odometry::VioImuOnlyStretch*> long_ones;
  for (const odometry::VioImuOnlyStretch& s : stats.imu_only_stretches)
    if (s.t_last - s.t_first >= kLongImuOnlyStretchS) long_ones.push_back(&s);
  const double share = stats.ImuOnlyShare();
  const bool over = stats.imu_only_frames > 0 && share > max_share;
  if (long_ones.empty() && !over) return 0;
  std::ostringstream w;
  w << std::fixed << std::setprecision(1) << "plucker vio: warning: " << stats.imu_only_frames
    << " of " << stats.window_frames << " frames (" << 100.0 * share
    << " %) had no visual update (the IMU alone: no landmark tracked)";
  const std::size_t shown = std::min<std::size_t>(long_ones.size(), 5);
  if (shown > 0) w << "; stretches of " << kLongImuOnlyStretchS << " s or more: frames ";
  for (std::size_t k = 0; k < shown; ++k) {
    const odometry::VioImuOnlyStretch& s = *long_ones[k];
    w << (k > 0 ? ", " : "") << s.first << "-" << s.last << " (" << std::setprecision(2)
      << s.t_first << "-" << s.t_last << " s)";
  }
  if (long_ones.size() > shown) w << " and " << long_ones.size() - shown << " more";
  std::cerr << w.str() << "\n";
  if (!over) return 0;
  std::cerr << "plucker vio: warning: the IMU-only share " << std::fixed << std::setprecision(3)
            << share << " exceeds max_imu_only_share " << max_share
            << ": the trajectory is not trustworthy (exit code " << kExitImuOnly << ")\n";
  return kExitImuOnly;
}

std::vector<VioReport::KeyframeChi2> InconsistentKeyframes(const VioReport& report,
                                                           double max_chi2) {
  std::vector<VioReport::KeyframeChi2> out;
  if (max_chi2 == 0.0) return out;  // off
  for (const VioReport::KeyframeChi2& k : report.keyframe_chi2)
    if (!(k.chi2 <= max_chi2)) out.push_back(k);
  return out;
}

int WarnInconsistent(const std::vector<VioReport::KeyframeChi2>& inconsistent, double max_chi2) {
  if (inconsistent.empty()) return 0;
  std::ostringstream w;
  w << std::fixed << "plucker vio: warning: " << inconsistent.size()
    << " keyframes where the IMU and the vision disagree (IMU factor chi2 over "
       "max_keyframe_imu_chi2 "
    << std::setprecision(1) << max_chi2 << "): frames ";
  const std::size_t shown = std::min<std::size_t>(inconsistent.size(), 5);
  for (std::size_t k = 0; k < shown; ++k) {
    const VioReport::KeyframeChi2& c = inconsistent[k];
    w << (k > 0 ? ", " : "") << c.frame << " (" << std::setprecision(2) << c.time << " s, chi2 "
      << std::setprecision(1) << c.chi2 << ")";
  }
  if (inconsistent.size() > shown) w << " and " << inconsistent.size() - shown << " more";
  std::cerr << w.str() << ": the trajectory is not trustworthy (exit code " << kExitImuOnly
            << ")\n";
  return kExitImuOnly;
}

std::vector<int> WriteVioTrajectory(const std::string& path,
                                    const std::vector<odometry::VioFrameRecord>& records,
                                    bool online, std::optional<std::int64_t> clock_origin_ns) {
  std::vector<double> times;
  std::vector<SE3d> poses;
  std::vector<int> written;
  for (const odometry::VioFrameRecord& r : records) {
    if (!r.T_w_b) continue;
    times.push_back(r.time);
    poses.push_back(*r.T_w_b);
    written.push_back(r.frame);
  }
  const std::string what =
      online ? odometry::kOnlineTrajectoryNote : odometry::kRefinedTrajectoryNote;
  if (clock_origin_ns) {
    io::WriteTumTrajectoryOnClock(path, *clock_origin_ns, times, poses, {what});
  } else {
    io::WriteTumTrajectory(path, times, poses, {what});
  }
  return written;
}

namespace {

constexpr const char* kAxisColors[3] = {"#d62728", "#2ca02c", "#1f77b4"};  // x, y, z
constexpr const char* kGtAxisColors[3] = {"#f4a3a3", "#a3dba3", "#a3c8e8"};

// A panel of the estimate's x, y, z against time, with the ground truth's beside when given.
eval::SeriesPanel AxesPanel(const std::string& title, const std::string& unit,
                            const std::vector<double>& times,
                            const std::vector<Eigen::Vector3d>& est,
                            const std::vector<Eigen::Vector3d>& gt) {
  eval::SeriesPanel panel;
  panel.title = title;
  panel.x_label = "time [s]";
  panel.y_label = unit;
  for (int axis = 0; axis < 3; ++axis) {
    for (const auto* values : {&gt, &est}) {
      if (values->empty()) continue;
      eval::PlotSeries series;
      const bool is_gt = values == &gt;
      series.label = std::string(1, "xyz"[axis]) + (is_gt ? " ground truth" : " estimate");
      series.color = is_gt ? kGtAxisColors[axis] : kAxisColors[axis];
      for (std::size_t i = 0; i < values->size(); ++i)
        series.points.emplace_back(times[i], (*values)[i](axis));
      panel.series.push_back(series);
    }
  }
  return panel;
}

// Height (z of the aligned estimate and of the ground truth) and the biases of the online
// estimate per frame against the ground truth's (EuRoC), against time.
std::string HeightAndBiasesSvg(const VioInput& in, const std::vector<double>& times,
                               const std::vector<SE3d>& est_aligned, const std::vector<SE3d>& gt,
                               const std::vector<double>& bias_times,
                               const std::vector<sensor::BodyState>& states) {
  eval::SeriesFigure figure;
  figure.title = "plucker vio: height and IMU biases";
  figure.subtitle = in.source;
  eval::SeriesPanel height;
  height.title = "height (z, aligned as the top view)";
  height.x_label = "time [s]";
  height.y_label = "z [m]";
  for (const auto* poses : {&gt, &est_aligned}) {
    if (poses->empty()) continue;
    eval::PlotSeries series;
    series.label = poses == &gt ? "ground truth" : "estimate";
    series.color = poses == &gt ? "#222222" : "#1f77b4";
    for (std::size_t i = 0; i < poses->size(); ++i)
      series.points.emplace_back(times[i], (*poses)[i].translation().z());
    height.series.push_back(series);
  }
  figure.panels.push_back(height);
  std::vector<Eigen::Vector3d> gyro, accel, gt_gyro, gt_accel;
  for (const sensor::BodyState& s : states) {
    gyro.push_back(s.bias.gyro);
    accel.push_back(s.bias.accel);
  }
  for (const sensor::BodyState& s : NearestGroundTruthStates(in, bias_times)) {
    gt_gyro.push_back(s.bias.gyro);
    gt_accel.push_back(s.bias.accel);
  }
  figure.panels.push_back(AxesPanel("gyroscope bias", "rad/s", bias_times, gyro, gt_gyro));
  figure.panels.push_back(AxesPanel("accelerometer bias", "m/s^2", bias_times, accel, gt_accel));
  for (eval::SeriesPanel& p : figure.panels) p.message = "no estimate";
  return eval::RenderSeriesFigureSvg(figure);
}

}  // namespace

void WriteVioPlot(const std::string& path, const VioInput& in,
                  const std::vector<odometry::VioFrameRecord>& records,
                  const std::vector<odometry::VioFrameRecord>& online) {
  std::vector<double> bias_times;
  std::vector<sensor::BodyState> states;
  for (const odometry::VioFrameRecord& r : online) {
    if (!r.window) continue;
    bias_times.push_back(r.time);
    states.push_back(r.window->state);
  }
  std::vector<SE3d> est, gt;
  std::vector<double> times;
  for (const odometry::VioFrameRecord& r : records) {
    if (!r.T_w_b) continue;
    est.push_back(*r.T_w_b);
    times.push_back(r.time);
    if (in.gt_T_w_b) gt.push_back((*in.gt_T_w_b)[r.frame]);
  }
  if (!in.gt_states.empty()) gt = NearestGroundTruth(in, times);
  eval::TrajectoryPlot plot;
  plot.subtitle = in.source;
  if (!gt.empty()) {
    const eval::AteResult ate = eval::ComputeAte(gt, est, {eval::AlignmentMode::kPositionYaw});
    est = ate.aligned_estimate;
    std::ostringstream title;
    title << "plucker vio: ATE (position+yaw aligned) RMSE " << std::setprecision(3)
          << ate.translation_m.rmse << " m over " << gt.size() << " poses";
    plot.title = title.str();
    for (const SE3d& T : gt) plot.positions_gt.push_back(T.translation());
    eval::PlotSeries series;
    series.label = "position error";
    for (std::size_t i = 0; i < gt.size(); ++i)
      series.points.emplace_back(times[i], ate.translation_errors[i]);
    plot.error_series.push_back(series);
    plot.error_title = "position error over time";
    plot.error_x_label = "time [s]";
    plot.error_y_label = "position error [m]";
  } else {
    plot.title = "plucker vio: body trajectory (no ground truth)";
    plot.error_message = "no ground truth in the input";
  }
  for (const SE3d& T : est) plot.positions_est.push_back(T.translation());
  io::WriteFileAtomically(
      path, eval::StackSvgDocuments({eval::RenderTrajectoryPlotSvg(plot),
                                     HeightAndBiasesSvg(in, times, est, gt, bias_times, states)}));
}

}  // namespace app
}  // namespace plucker
