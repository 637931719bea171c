#include "vo_output.h"

#include <algorithm>
#include <ctime>
#include <iomanip>
#include <iostream>

#include "pipeline_json.h"
#include "plucker/io/io_error.h"
#include "plucker/io/trajectory_io.h"

namespace plucker {
namespace app {
namespace {

// The JSON name of a VoStage: read, the front end's stages, the window's stages, other.
const char* VoStageName(int s) {
  if (s == kRead) return kReadStageName;
  if (s < kTracking) return kFrontendStageNames[s - kPoints];
  if (s < kOther) return kWindowStageNames[s - kTracking];
  return kOtherStageName;
}

nlohmann::json MapJson(const odometry::MonocularMap& m) {
  return {{"frames", {m.first, m.second}},
          {"keyframes", m.keyframes},
          {"after_lost_frame", m.after_lost_frame},
          {"scale", m.stereo ? "metric" : (m.chained_baseline ? "chained" : "unit_baseline")},
          {"baseline", m.chained_baseline.value_or(1.0)},
          {"points", m.points},
          {"lines", m.lines},
          {"tries", m.tries},
          {"chi2_z", m.chi2_z}};
}

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * v.size()));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

// The window's points and lines over the run: means over the tracked frames (held in the window,
// tracked), totals and means over the keyframes' solves (new, residuals, culled, RMS), and the
// new-line triangulation's rejections (summary "landmarks").
nlohmann::json LandmarkStatisticsJson(const std::vector<odometry::MonocularFrameRecord>& records) {
  double held[2] = {}, tracked[2] = {}, rms[2] = {};
  int frames = 0, solves = 0, line_solves = 0, added[2] = {}, residuals = 0, line_residuals = 0,
      culled = 0, culled_lines = 0, candidates = 0, small_parallax = 0, ill = 0, other = 0;
  for (const odometry::MonocularFrameRecord& rec : records) {
    if (!rec.window || !rec.has_pose) continue;
    const window::WindowFrameResult& r = *rec.window;
    ++frames;
    held[0] += r.window_points;
    held[1] += r.window_lines;
    tracked[0] += r.tracked_points;
    tracked[1] += r.tracked_lines;
    if (!r.keyframe) continue;
    ++solves;
    added[0] += r.new_points;
    added[1] += r.new_lines;
    residuals += r.residuals;
    line_residuals += r.line_residuals;
    culled += r.culled_observations;
    culled_lines += r.culled_line_observations;
    rms[0] += r.point_rms_sigmas;
    rms[1] += r.line_rms_sigmas;
    line_solves += r.line_residuals > 0;
    candidates += r.line_candidates;
    small_parallax += r.line_small_parallax;
    ill += r.line_ill_conditioned;
    other += r.line_other_rejections;
  }
  const auto mean = [](double sum, int n) { return n > 0 ? sum / n : 0.0; };
  return {{"tracked_frames", frames},
          {"mean_window_points", mean(held[0], frames)},
          {"mean_window_lines", mean(held[1], frames)},
          {"mean_tracked_points", mean(tracked[0], frames)},
          {"mean_tracked_lines", mean(tracked[1], frames)},
          {"keyframe_solves", solves},
          {"new_points", added[0]},
          {"new_lines", added[1]},
          {"mean_point_residuals", mean(residuals - line_residuals, solves)},
          {"mean_line_residuals", mean(line_residuals, solves)},
          {"culled_point_observations", culled - culled_lines},
          {"culled_line_observations", culled_lines},
          {"mean_point_rms_sigmas", mean(rms[0], solves)},
          {"mean_line_rms_sigmas", mean(rms[1], line_solves)},  // of the solves with lines
          {"line_candidates", candidates},
          {"line_small_parallax", small_parallax},
          {"line_ill_conditioned", ill},
          {"line_other_rejections", other}};
}

}  // namespace

void WriteVoJson(const std::string& path, const odometry::MonocularOdometry& vo,
                 const VoConfig& config, const VoRunLog& log) {
  const std::vector<odometry::MonocularFrameRecord>& records = vo.Trajectory();
  const int n = static_cast<int>(records.size());
  nlohmann::json list = nlohmann::json::array();
  double stage_total[kNumVoStages] = {};
  double init_ms = log.finish_ms;
  std::vector<double> frame_ms;
  for (int i = 0; i < n; ++i) {
    const odometry::MonocularFrameRecord& r = records[i];
    const VoFrameLog& f = log.frames[i];
    nlohmann::json j = r.window ? WindowFrameJson(*r.window, false) : nlohmann::json::object();
    if (!f.frontend.is_null()) j["frontend"] = f.frontend;
    j["frame"] = i;
    j["time"] = r.time;
    j["status"] = odometry::ToString(r.source);
    j["keyframe"] = r.keyframe;
    j["online"] = {{"status", odometry::ToString(f.online)}, {"has_pose", f.online_pose}};
    double total = 0.0;
    for (int s = 0; s < kNumVoStages; ++s) {
      j["ms"][VoStageName(s)] = f.ms[s];
      stage_total[s] += f.ms[s];
      total += f.ms[s];
    }
    j["ms"]["total"] = total;
    if (!f.frontend.is_null())  // the image's own stages, where they were before (kept)
      for (int s = kRead; s <= kLines; ++s) j["frontend"]["ms"][VoStageName(s)] = f.ms[s];
    frame_ms.push_back(total);
    if (f.online != odometry::MonocularStatus::kTracking &&
        f.online != odometry::MonocularStatus::kLost)
      init_ms += f.ms[kOther];
    list.push_back(j);
  }
  const odometry::MonocularSummary& sum = vo.Summary();
  const int wf = sum.window_frames;
  double window_ms = 0.0;
  nlohmann::json stages = nlohmann::json::object(), pipeline = nlohmann::json::object();
  for (int s = kTracking; s <= kMargin; ++s) {
    window_ms += stage_total[s];
    stages[VoStageName(s)] = wf > 0 ? stage_total[s] / wf : 0.0;
  }
  double cpu_ms = log.finish_ms;
  for (int s = 0; s < kNumVoStages; ++s) {
    pipeline[VoStageName(s)] = n > 0 ? stage_total[s] / n : 0.0;
    cpu_ms += stage_total[s];
  }
  nlohmann::json frontend = nlohmann::json::object();
  for (int s = kPoints; s <= kLines; ++s)
    frontend[VoStageName(s)] = n > 0 ? stage_total[s] / n : 0.0;
  nlohmann::json maps = nlohmann::json::array();
  for (const odometry::MonocularMap& m : vo.Maps()) maps.push_back(MapJson(m));
  const window::SlidingWindowOptions& w = config.window;
  nlohmann::json out;
  out["frames"] = list;
  out["summary"] = {
      {"frames", n},
      {"initialization_frames", maps.empty() ? nlohmann::json() : maps.front()["frames"]},
      {"maps", maps},
      {"reinitializations", static_cast<int>(maps.size()) - 1},
      {"keyframes", sum.keyframes},
      {"lost_frames", sum.lost_frames},
      {"pnp_recoveries", sum.pnp_recoveries},
      {"landmarks", LandmarkStatisticsJson(records)},
      {"tracked_ratio_mapped_segments", w.tracked_ratio_mapped_segments},
      {"marginalized_keyframes", sum.marginalized_keyframes},
      {"failed_marginalizations", sum.failed_marginalizations},
      {"use_lines", w.use_lines},
      {"keep_marginalized_lines", w.keep_marginalized_lines},
      {"retain_line_observer_poses", w.retain_line_observer_poses},
      {"max_retained_poses", w.max_retained_poses},
      {"retained_overflow_into_prior", w.retained_overflow_into_prior},
      {"prior_on_poses_only", w.prior_blocks == window::SlidingWindowOptions::PriorBlocks::kPoses},
      {"point_stride", log.point_stride},
      {"read_ms", log.read_ms},
      {"frontend_mean_ms", frontend},
      {"skipped_images", log.skipped_images},
      {"initialization_ms", init_ms},
      {"mean_frame_ms", wf > 0 ? window_ms / wf : 0.0},
      {"mean_stage_ms", stages},
      {"total_wall_ms", log.total_wall_ms},
      {"frames_per_second_cpu", window_ms > 0 ? 1e3 * wf / window_ms : 0.0},
      {"pipeline_mean_stage_ms", pipeline},
      {"pipeline_frame_ms_p50", Quantile(frame_ms, 0.5)},
      {"pipeline_frame_ms_p95", Quantile(frame_ms, 0.95)},
      {"pipeline_frame_ms_max", Quantile(frame_ms, 1.0)},
      {"frames_per_second_cpu_with_frontend", cpu_ms > 0 ? 1e3 * n / cpu_ms : 0.0},
      {"process_cpu_ms", 1e3 * static_cast<double>(std::clock()) / CLOCKS_PER_SEC}};
  io::WriteFileAtomically(path, out.dump(1) + "\n");
}

void WriteVoOutputs(const VoOutputs& o, const odometry::MonocularOdometry& vo,
                    const VoConfig& config, const std::vector<std::optional<SE3d>>& online,
                    const VoRunLog& log) {
  if (vo.Maps().empty()) {
    throw io::IoError(o.source, "cannot initialise (" + vo.StartFailure() +
                                    "): too few point tracks with parallax");
  }
  if (!vo.RestartFailure().empty()) {
    std::cerr << "plucker vo: warning: cannot re-initialise after frame " << vo.RestartFailedAfter()
              << " (" << vo.RestartFailure() << "); the remaining frames keep the last pose\n";
  }
  std::vector<SE3d> poses;
  for (const odometry::MonocularFrameRecord& r : vo.Trajectory()) poses.push_back(r.T_w_c);
  io::WriteKittiPoses(o.out, poses);
  if (!o.out_online.empty()) io::WriteKittiPosesWithGaps(o.out_online, online);
  if (!o.json.empty()) WriteVoJson(o.json, vo, config, log);
  const odometry::MonocularSummary& s = vo.Summary();
  const std::size_t n = log.frames.size();
  if (!o.quiet) {
    double cpu = log.finish_ms;
    for (const VoFrameLog& f : log.frames)
      for (double ms : f.ms) cpu += ms;
    std::cerr << "plucker vo: " << n << " frames (initialised on frames " << vo.Maps()[0].first
              << " and " << vo.Maps()[0].second << "), " << s.keyframes << " keyframes, "
              << s.lost_frames << " lost, " << vo.Maps().size() - 1 << " re-initialisations, "
              << std::fixed << std::setprecision(2) << cpu / n
              << " ms CPU per frame (front end included); wrote " << o.out << "\n";
  }
  if (s.lost_frames > 0) {
    std::cerr << "plucker vo: warning: " << s.lost_frames
              << " frames could not be tracked (their pose is the constant-velocity prediction, or "
                 "the previous pose)\n";
  }
}

}  // namespace app
}  // namespace plucker
