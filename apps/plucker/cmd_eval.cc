// `plucker eval kitti|ate|rpe`: trajectory metrics of an estimate against a ground truth, as a
// table (default) or JSON (--json), with an optional SVG figure (--plot).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "plucker/eval/alignment.h"
#include "plucker/eval/association.h"
#include "plucker/eval/ate.h"
#include "plucker/eval/kitti_metric.h"
#include "plucker/eval/plot.h"
#include "plucker/eval/rpe.h"
#include "plucker/io/io_error.h"
#include "plucker/io/trajectory_io.h"
#include "run_guarded.h"

namespace plucker {
namespace app {
namespace {

using nlohmann::json;

struct EvalArgs {
  std::string gt, est, times_gt, times_est;
  std::string format = "auto";
  std::string plot, plane = "auto";
  bool json = false;
  double max_dt = 0.02;
  // ate / rpe
  std::string align;
  double delta = 1.0;
  std::string delta_unit = "frames";
};

void AddCommonOptions(CLI::App* cmd, EvalArgs* a) {
  cmd->add_option("--gt", a->gt, "Ground-truth trajectory (KITTI poses or TUM)")->required();
  cmd->add_option("--est", a->est, "Estimated trajectory (KITTI poses or TUM)")->required();
  cmd->add_option("--format", a->format,
                  "File format of both files: 12 numbers a line = kitti, "
                  "8 = tum (t tx ty tz qx qy qz qw)")
      ->check(CLI::IsMember({"auto", "kitti", "tum"}))
      ->capture_default_str();
  cmd->add_option("--gt-times", a->times_gt,
                  "times.txt for a KITTI ground truth (enables association by time)");
  cmd->add_option("--est-times", a->times_est, "times.txt for a KITTI estimate");
  cmd->add_option("--max-dt", a->max_dt,
                  "Largest timestamp difference [s] when pairing TUM poses by time")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_flag("--json", a->json, "Print machine-readable JSON instead of a table");
  cmd->add_option("--plot", a->plot, "Write an SVG figure (top view + error along the path)");
  cmd->add_option("--plane", a->plane, "Plane of the top view (auto: the two largest extents)")
      ->check(CLI::IsMember({"auto", "xy", "xz", "yz"}))
      ->capture_default_str();
}

// Loaded and associated input.
struct Input {
  io::Trajectory gt, est;
  eval::AssociatedTrajectories pairs;
};

bool SameFile(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (std::filesystem::equivalent(a, b, ec) && !ec) return true;
  std::error_code ec_a, ec_b;
  const std::filesystem::path canonical_a = std::filesystem::weakly_canonical(a, ec_a);
  const std::filesystem::path canonical_b = std::filesystem::weakly_canonical(b, ec_b);
  return !ec_a && !ec_b && canonical_a == canonical_b;
}

void CheckPlotPath(const EvalArgs& a) {
  if (a.plot.empty()) return;
  for (const std::string* input : {&a.gt, &a.est, &a.times_gt, &a.times_est}) {
    if (!input->empty() && SameFile(a.plot, *input)) {
      throw std::invalid_argument("--plot " + a.plot +
                                  " is an input file; refusing to overwrite it");
    }
  }
  const std::string ext = std::filesystem::path(a.plot).extension().string();
  if (ext != ".svg" && ext != ".SVG") {
    throw std::invalid_argument("--plot " + a.plot +
                                ": only SVG is written (name it .svg; `rsvg-convert` makes a PNG)");
  }
}

Input Load(const EvalArgs& a) {
  CheckPlotPath(a);
  const io::TrajectoryFormat format = io::ParseTrajectoryFormat(a.format);
  Input in;
  in.gt = io::ReadTrajectory(a.gt, format);
  in.est = io::ReadTrajectory(a.est, format);
  auto attach_times = [](const std::string& times_path, const std::string& poses_path,
                         io::Trajectory* t) {
    if (times_path.empty()) return;
    std::vector<double> times = io::ReadTimes(times_path);
    if (times.size() != t->poses.size()) {
      throw io::IoError(times_path, std::to_string(times.size()) + " times but " + poses_path +
                                        " has " + std::to_string(t->poses.size()) + " poses");
    }
    t->times = std::move(times);
  };
  attach_times(a.times_gt, a.gt, &in.gt);
  attach_times(a.times_est, a.est, &in.est);
  try {
    if (!in.gt.times.empty() && !in.est.times.empty()) {
      eval::AssociationOptions options;
      options.max_time_difference = a.max_dt;
      in.pairs =
          eval::AssociateByTime(in.gt.times, in.gt.poses, in.est.times, in.est.poses, options);
    } else {
      in.pairs = eval::AssociateByIndex(in.gt.poses, in.est.poses);
    }
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(a.gt + " vs " + a.est + ": " + e.what());
  }
  return in;
}

std::string Fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

json StatsJson(const eval::ErrorStatistics& s) {
  return json{{"count", s.count}, {"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median},
              {"std", s.std_dev}, {"min", s.min},   {"max", s.max}};
}

json AssociationJson(const eval::AssociatedTrajectories& p) {
  json j{{"mode", p.by_time ? "time" : "index"},
         {"gt_poses", p.count_gt},
         {"est_poses", p.count_est},
         {"pairs", p.gt.size()}};
  if (p.by_time) j["max_time_difference_s"] = p.max_time_difference_used;
  return j;
}

json AlignmentJson(const eval::Similarity& S, bool roll_from_orientations) {
  json R = json::array();
  for (int r = 0; r < 3; ++r) R.push_back({S.R(r, 0), S.R(r, 1), S.R(r, 2)});
  return json{{"scale", S.scale},
              {"R", R},
              {"t", {S.t.x(), S.t.y(), S.t.z()}},
              {"roll_from_orientations", roll_from_orientations}};
}

const char kRollNote[] =
    "  note           positions nearly collinear: the roll about the line was taken from the "
    "orientations\n";

template <typename T>
json OptionalJson(const std::optional<T>& v) {
  return v ? json(*v) : json(nullptr);
}

void PrintHeader(std::ostream& out, const EvalArgs& a, const Input& in) {
  out << "  ground truth   " << a.gt << " (" << in.gt.poses.size() << " poses)\n"
      << "  estimate       " << a.est << " (" << in.est.poses.size() << " poses)\n";
  if (in.pairs.by_time) {
    out << "  association    by time: " << in.pairs.gt.size() << " pairs (max |dt| "
        << Fixed(in.pairs.max_time_difference_used, 4) << " s <= " << a.max_dt << " s); "
        << in.pairs.count_est - static_cast<int>(in.pairs.gt.size())
        << " estimate poses unpaired\n";
  } else {
    out << "  association    frame by frame: " << in.pairs.gt.size() << " pairs\n";
  }
}

void PrintStats(std::ostream& out, const std::string& name, const eval::ErrorStatistics& s,
                const std::string& unit, int decimals) {
  const std::string label = name + " [" + unit + "]";
  out << "  " << label << std::string(label.size() < 22 ? 22 - label.size() : 1, ' ') << "rmse "
      << Fixed(s.rmse, decimals) << "  mean " << Fixed(s.mean, decimals) << "  median "
      << Fixed(s.median, decimals) << "  std " << Fixed(s.std_dev, decimals) << "  max "
      << Fixed(s.max, decimals) << "\n";
}

eval::PlotPlane Plane(const EvalArgs& a) {
  eval::PlotPlane plane = eval::PlotPlane::kAuto;
  eval::ParsePlotPlane(a.plane, &plane);
  return plane;
}

void WritePlot(const EvalArgs& a, const eval::TrajectoryPlot& plot) {
  if (a.plot.empty()) return;
  io::WriteFileAtomically(a.plot, eval::RenderTrajectoryPlotSvg(plot));
  if (!a.json) std::cout << "  plot           " << a.plot << "\n";
}

std::string Subtitle(const EvalArgs& a) {
  return "ground truth: " + a.gt + "  |  estimate: " + a.est;
}

std::vector<Eigen::Vector2d> Zip(const std::vector<double>& x, const std::vector<double>& y) {
  std::vector<Eigen::Vector2d> p;
  for (std::size_t i = 0; i < x.size() && i < y.size(); ++i) p.emplace_back(x[i], y[i]);
  return p;
}

// ---------------------------------------------------------------------------------------------
void RunKitti(const EvalArgs& a) {
  const Input in = Load(a);
  const eval::KittiResult r = eval::ComputeKittiMetric(in.pairs.gt, in.pairs.est);
  const std::string no_segment = "no segment: the ground-truth path is " + Fixed(r.path_length, 1) +
                                 " m, shorter than the shortest KITTI length (100 m)";
  if (a.json) {
    json per_length = json::array();
    for (const eval::KittiLengthResult& l : r.per_length) {
      per_length.push_back(
          {{"length_m", l.length},
           {"segments", l.segment_count},
           {"translation_error_percent", OptionalJson(l.translation_error_percent)},
           {"rotation_error_deg_per_100m", OptionalJson(l.rotation_error_deg_per_100m)}});
    }
    json j{{"metric", "kitti"},
           {"gt", a.gt},
           {"est", a.est},
           {"association", AssociationJson(in.pairs)},
           {"status", r.has_segments() ? "ok" : "no segment"},
           {"path_length_m", r.path_length},
           {"segments", r.segment_count},
           {"translation_error_percent", OptionalJson(r.translation_error_percent)},
           {"rotation_error_deg_per_m", OptionalJson(r.rotation_error_deg_per_m)},
           {"rotation_error_deg_per_100m", OptionalJson(r.rotation_error_deg_per_100m)},
           {"per_length", per_length}};
    if (!r.has_segments()) j["message"] = no_segment;
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << "KITTI odometry metric (devkit: lengths 100..800 m, a start every 10 frames)\n";
    PrintHeader(std::cout, a, in);
    std::cout << "  path length    " << Fixed(r.path_length, 1) << " m\n";
    if (!r.has_segments()) {
      std::cout << "  result         " << no_segment
                << "\n                 (use `plucker eval rpe` or `plucker eval ate`)\n";
    } else {
      std::cout << "  segments       " << r.segment_count << "\n"
                << "  translation    " << Fixed(*r.translation_error_percent, 4) << " %\n"
                << "  rotation       " << Fixed(*r.rotation_error_deg_per_m, 6) << " deg/m  ("
                << Fixed(*r.rotation_error_deg_per_100m, 4) << " deg/100 m)\n\n"
                << "  length [m]  segments  t_err [%]  r_err [deg/100 m]\n";
      for (const eval::KittiLengthResult& l : r.per_length) {
        char line[128];
        if (l.segment_count > 0) {
          std::snprintf(line, sizeof(line), "  %10.0f  %8d  %9.4f  %17.4f\n", l.length,
                        l.segment_count, *l.translation_error_percent,
                        *l.rotation_error_deg_per_100m);
        } else {
          std::snprintf(line, sizeof(line), "  %10.0f  %8d  %9s  %17s\n", l.length, 0, "-", "-");
        }
        std::cout << line;
      }
    }
  }
  if (!a.plot.empty()) {
    eval::TrajectoryPlot plot;
    plot.title = r.has_segments()
                     ? "KITTI metric: translation " + Fixed(*r.translation_error_percent, 3) +
                           " %, rotation " + Fixed(*r.rotation_error_deg_per_100m, 3) +
                           " deg/100 m (" + std::to_string(r.segment_count) + " segments)"
                     : "KITTI metric: no segment (path " + Fixed(r.path_length, 1) + " m < 100 m)";
    plot.subtitle = Subtitle(a);
    plot.positions_gt = eval::Positions(in.pairs.gt);
    plot.positions_est = eval::Positions(in.pairs.est);
    plot.label_est = "estimate (not aligned)";
    plot.plane = Plane(a);
    plot.error_title = "Segment translation error vs. start of segment";
    plot.error_y_label = "translation error [%]";
    plot.error_message = no_segment;
    static const char* kColors[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728",
                                    "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"};
    int k = 0;
    for (const eval::KittiLengthResult& l : r.per_length) {
      eval::PlotSeries series;
      series.label = Fixed(l.length, 0) + " m";
      series.color = kColors[k++ % 8];
      for (const eval::KittiSegment& s : r.segments) {
        if (s.length == l.length) {
          series.points.emplace_back(r.distance[s.first], 100.0 * s.translation_error);
        }
      }
      if (!series.points.empty()) plot.error_series.push_back(series);
    }
    if (!r.has_segments()) {
      // Something useful instead of an empty panel: the raw position error (both trajectories
      // start at the identity in KITTI files, so no alignment), clearly labelled as such.
      plot.error_title = "No KITTI segment: position error per pose (not aligned)";
      plot.error_y_label = "position error [m]";
      eval::PlotSeries series;
      series.label = "|p_est - p_gt| (not the KITTI metric)";
      series.color = "#d62728";
      for (std::size_t i = 0; i < in.pairs.gt.size(); ++i) {
        series.points.emplace_back(
            r.distance[i], (in.pairs.est[i].translation() - in.pairs.gt[i].translation()).norm());
      }
      plot.error_series.push_back(series);
    }
    WritePlot(a, plot);
  }
}

// ---------------------------------------------------------------------------------------------
void RunAte(const EvalArgs& a) {
  const Input in = Load(a);
  eval::AteOptions options;
  options.align = *eval::ParseAlignmentMode(a.align);
  const eval::AteResult r = eval::ComputeAte(in.pairs.gt, in.pairs.est, options);
  if (a.json) {
    std::cout << json{{"metric", "ate"},
                      {"gt", a.gt},
                      {"est", a.est},
                      {"align", a.align},
                      {"association", AssociationJson(in.pairs)},
                      {"alignment", AlignmentJson(r.alignment, r.roll_from_orientations)},
                      {"translation_m", StatsJson(r.translation_m)},
                      {"rotation_deg", StatsJson(r.rotation_deg)}}
                     .dump(2)
              << "\n";
  } else {
    std::cout << "Absolute trajectory error (alignment: " << a.align << ")\n";
    PrintHeader(std::cout, a, in);
    if (options.align == eval::AlignmentMode::kSim3) {
      std::cout << "  sim3 scale     " << Fixed(r.alignment.scale, 6) << "\n";
    }
    if (r.roll_from_orientations) std::cout << kRollNote;
    PrintStats(std::cout, "ATE translation", r.translation_m, "m", 4);
    PrintStats(std::cout, "ATE rotation", r.rotation_deg, "deg", 4);
  }
  if (!a.plot.empty()) {
    eval::TrajectoryPlot plot;
    plot.title = "ATE (" + a.align + " aligned): RMSE " + Fixed(r.translation_m.rmse, 3) +
                 " m, max " + Fixed(r.translation_m.max, 3) + " m over " +
                 std::to_string(r.translation_m.count) + " poses";
    plot.subtitle = Subtitle(a);
    plot.positions_gt = eval::Positions(in.pairs.gt);
    plot.positions_est = eval::Positions(r.aligned_estimate);
    plot.label_est = a.align == "none" ? "estimate" : "estimate (" + a.align + " aligned)";
    plot.plane = Plane(a);
    plot.error_title = "Position error per pose";
    plot.error_y_label = "position error [m]";
    eval::PlotSeries series;
    series.label = "ATE (RMSE " + Fixed(r.translation_m.rmse, 3) + " m)";
    series.color = "#d62728";
    series.points = Zip(r.distance, r.translation_errors);
    plot.error_series.push_back(series);
    WritePlot(a, plot);
  }
}

// ---------------------------------------------------------------------------------------------
void RunRpe(const EvalArgs& a) {
  const Input in = Load(a);
  eval::RpeOptions options;
  options.align = *eval::ParseAlignmentMode(a.align);
  options.delta = a.delta;
  options.unit = a.delta_unit == "m" ? eval::DeltaUnit::kMeters : eval::DeltaUnit::kFrames;
  const eval::RpeResult r = eval::ComputeRpe(in.pairs.gt, in.pairs.est, options);
  std::ostringstream delta;
  delta << a.delta
        << (options.unit == eval::DeltaUnit::kMeters ? " m"
            : a.delta == 1.0                         ? " frame"
                                                     : " frames");
  if (a.json) {
    std::cout << json{{"metric", "rpe"},
                      {"gt", a.gt},
                      {"est", a.est},
                      {"delta", a.delta},
                      {"delta_unit", a.delta_unit},
                      {"align", a.align},
                      {"association", AssociationJson(in.pairs)},
                      {"pairs", r.first.size()},
                      {"alignment", AlignmentJson(r.alignment, r.roll_from_orientations)},
                      {"translation_m", StatsJson(r.translation_m)},
                      {"rotation_deg", StatsJson(r.rotation_deg)}}
                     .dump(2)
              << "\n";
  } else {
    std::cout << "Relative pose error over " << delta.str() << " (alignment: " << a.align << ")\n";
    PrintHeader(std::cout, a, in);
    std::cout << "  frame pairs    " << r.first.size() << "\n";
    PrintStats(std::cout, "RPE translation", r.translation_m, "m", 4);
    PrintStats(std::cout, "RPE rotation", r.rotation_deg, "deg", 4);
  }
  if (!a.plot.empty()) {
    eval::TrajectoryPlot plot;
    plot.title = "RPE over " + delta.str() + ": translation RMSE " +
                 Fixed(r.translation_m.rmse, 4) + " m, rotation RMSE " +
                 Fixed(r.rotation_deg.rmse, 4) + " deg";
    plot.subtitle = Subtitle(a);
    plot.positions_gt = eval::Positions(in.pairs.gt);
    plot.positions_est = eval::Positions(r.aligned_estimate);
    plot.label_est = a.align == "none" ? "estimate" : "estimate (" + a.align + " aligned)";
    plot.plane = Plane(a);
    plot.error_title = "Relative translation error per frame pair";
    plot.error_y_label = "translation error over " + delta.str() + " [m]";
    eval::PlotSeries series;
    series.label = "RPE translation (RMSE " + Fixed(r.translation_m.rmse, 4) + " m)";
    series.color = "#d62728";
    series.markers = r.first.size() <= 200;
    series.points = Zip(r.distance, r.translation_errors);
    plot.error_series.push_back(series);
    WritePlot(a, plot);
  }
}

}  // namespace

void RegisterEval(CLI::App& app, int* exit_code) {
  CLI::App* eval_cmd = app.add_subcommand(
      "eval",
      "Evaluate against ground truth: trajectories (KITTI metric, ATE, RPE), line segments");
  eval_cmd->require_subcommand(1);

  auto kitti_args = std::make_shared<EvalArgs>();
  CLI::App* kitti = eval_cmd->add_subcommand(
      "kitti", "KITTI odometry metric: translation % and rotation deg/100 m over 100..800 m");
  AddCommonOptions(kitti, kitti_args.get());
  kitti->callback(
      [kitti_args, exit_code] { RunGuarded("eval", exit_code, [&] { RunKitti(*kitti_args); }); });

  auto ate_args = std::make_shared<EvalArgs>();
  ate_args->align = "se3";
  CLI::App* ate = eval_cmd->add_subcommand("ate", "Absolute trajectory error after alignment");
  AddCommonOptions(ate, ate_args.get());
  ate->add_option("--align", ate_args->align,
                  "Alignment: se3, sim3 (monocular), posyaw (position + yaw about z: what "
                  "visual-inertial odometry observes) or none")
      ->check(CLI::IsMember({"none", "se3", "sim3", "posyaw"}))
      ->capture_default_str();
  ate->callback(
      [ate_args, exit_code] { RunGuarded("eval", exit_code, [&] { RunAte(*ate_args); }); });

  auto rpe_args = std::make_shared<EvalArgs>();
  rpe_args->align = "none";
  CLI::App* rpe = eval_cmd->add_subcommand("rpe", "Relative pose error over a fixed delta");
  AddCommonOptions(rpe, rpe_args.get());
  rpe->add_option("--delta", rpe_args->delta, "Delta between the compared poses")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  rpe->add_option("--delta-unit", rpe_args->delta_unit,
                  "Unit of --delta: frames or m (ground-truth path length)")
      ->check(CLI::IsMember({"frames", "m"}))
      ->capture_default_str();
  rpe->add_option("--align", rpe_args->align,
                  "Alignment before RPE: none, se3 (no effect) or sim3 (rescales the estimate)")
      ->check(CLI::IsMember({"none", "se3", "sim3"}))
      ->capture_default_str();
  rpe->callback(
      [rpe_args, exit_code] { RunGuarded("eval", exit_code, [&] { RunRpe(*rpe_args); }); });

  AddEvalImu(eval_cmd, exit_code);
  AddEvalInit(eval_cmd, exit_code);
  RegisterEvalLines(*eval_cmd, exit_code);
  // `eval tracks` is added by the vision module (vision_commands.cc).
  RegisterEvalSfm(*eval_cmd, exit_code);
  RegisterEvalLidarBasin(*eval_cmd, exit_code);
}

}  // namespace app
}  // namespace plucker
