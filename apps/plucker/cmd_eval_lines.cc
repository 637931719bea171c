// `plucker eval lines --gt DIR --est DIR [--threshold 5] [--json]`: pixel-coverage precision,
// recall and F (eval/line_coverage.h) of the segment files of --est against those of --gt, per
// image and overall (lengths summed over all images), with the detection time per image when the
// estimate files record it (`# detection_ms`, written by `plucker lines detect`).
// Every <name>.txt of --gt is an image; a missing --est/<name>.txt counts as no detection and is
// reported. A malformed line in either folder is an error naming the file and the line.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "plucker/eval/line_coverage.h"
#include "plucker/io/io_error.h"
#include "plucker/io/segments.h"
#include "run_guarded.h"

namespace plucker {
namespace app {
namespace {

namespace fs = std::filesystem;

struct EvalLinesArgs {
  std::string gt, est;
  double threshold = 5.0;
  bool json = false;
};

struct ImageResult {
  std::string name;
  int gt_segments = 0, est_segments = 0;
  bool est_missing = false;
  eval::LineCoverage coverage;
  std::optional<double> ms;
};

std::vector<std::string> GroundTruthNames(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw io::IoError(dir, "not a folder");
  std::vector<std::string> names;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    if (e.is_regular_file(ec) && e.path().extension() == ".txt") {
      names.push_back(e.path().stem().string());
    }
  }
  std::sort(names.begin(), names.end());
  if (names.empty()) throw io::IoError(dir, "no ground-truth segment files (<name>.txt)");
  return names;
}

ImageResult EvaluateImage(const EvalLinesArgs& a, const std::string& name) {
  ImageResult r;
  r.name = name;
  const io::SegmentFile gt = io::ReadSegments((fs::path(a.gt) / (name + ".txt")).string());
  const std::string est_path = (fs::path(a.est) / (name + ".txt")).string();
  io::SegmentFile est;
  std::error_code ec;
  if (fs::exists(est_path, ec)) {
    est = io::ReadSegments(est_path);
  } else {
    r.est_missing = true;
  }
  r.gt_segments = static_cast<int>(gt.segments.size());
  r.est_segments = static_cast<int>(est.segments.size());
  r.coverage = eval::ComputeLineCoverage(est.segments, gt.segments, a.threshold);
  r.ms = est.detection_ms;
  return r;
}

nlohmann::json CoverageJson(const eval::LineCoverage& c) {
  return {{"precision", c.Precision()},
          {"recall", c.Recall()},
          {"f", c.F()},
          {"detected_length_px", c.detected_length},
          {"gt_length_px", c.gt_length}};
}

void Print(const EvalLinesArgs& a, const std::vector<ImageResult>& results,
           const eval::LineCoverage& overall, double mean_ms, int timed, int missing) {
  if (a.json) {
    nlohmann::json images = nlohmann::json::array();
    for (const ImageResult& r : results) {
      nlohmann::json j = CoverageJson(r.coverage);
      j["name"] = r.name;
      j["gt_segments"] = r.gt_segments;
      j["est_segments"] = r.est_segments;
      j["est_missing"] = r.est_missing;
      j["detection_ms"] = r.ms ? nlohmann::json(*r.ms) : nlohmann::json(nullptr);
      images.push_back(j);
    }
    nlohmann::json all = CoverageJson(overall);
    all["images"] = results.size();
    all["est_missing"] = missing;
    all["detection_ms_per_image"] = timed > 0 ? nlohmann::json(mean_ms) : nlohmann::json(nullptr);
    all["timed_images"] = timed;
    std::cout
        << nlohmann::json{{"metric", "line_coverage"},   {"gt", a.gt},     {"est", a.est},
                          {"threshold_px", a.threshold}, {"overall", all}, {"per_image", images}}
               .dump(2)
        << "\n";
    return;
  }
  std::printf("Line segment coverage at %g px: %s vs ground truth %s\n", a.threshold, a.est.c_str(),
              a.gt.c_str());
  std::printf("%-24s %6s %6s %7s %7s %7s %9s\n", "image", "gt", "est", "P", "R", "F", "ms");
  for (const ImageResult& r : results) {
    char ms[32] = "-";
    if (r.ms) std::snprintf(ms, sizeof(ms), "%.1f", *r.ms);
    std::printf("%-24s %6d %6d %7.3f %7.3f %7.3f %9s%s\n", r.name.c_str(), r.gt_segments,
                r.est_segments, r.coverage.Precision(), r.coverage.Recall(), r.coverage.F(), ms,
                r.est_missing ? "  (no estimate file)" : "");
  }
  char ms[32] = "-";
  if (timed > 0) std::snprintf(ms, sizeof(ms), "%.1f", mean_ms);
  std::printf("%-24s %6s %6s %7.3f %7.3f %7.3f %9s\n",
              ("overall (" + std::to_string(results.size()) + ")").c_str(), "", "",
              overall.Precision(), overall.Recall(), overall.F(), ms);
}

int RunEvalLines(const EvalLinesArgs& a) {
  if (!(a.threshold >= 0.0)) throw std::invalid_argument("--threshold must be >= 0");
  std::error_code ec;
  if (!fs::is_directory(a.est, ec)) throw io::IoError(a.est, "not a folder");
  std::vector<ImageResult> results;
  eval::LineCoverage overall;
  double ms_sum = 0.0;
  int ms_count = 0, missing = 0;
  for (const std::string& name : GroundTruthNames(a.gt)) {
    results.push_back(EvaluateImage(a, name));
    const ImageResult& r = results.back();
    overall += r.coverage;
    if (r.ms) ms_sum += *r.ms, ++ms_count;
    if (r.est_missing) {
      ++missing;
      std::cerr << "plucker eval lines: warning: " << a.est << "/" << name
                << ".txt missing: counted as no detection\n";
    }
  }
  Print(a, results, overall, ms_count > 0 ? ms_sum / ms_count : 0.0, ms_count, missing);
  return 0;
}

}  // namespace

void RegisterEvalLines(CLI::App& eval_cmd, int* exit_code) {
  auto a = std::make_shared<EvalLinesArgs>();
  CLI::App* cmd = eval_cmd.add_subcommand(
      "lines", "Line segments vs ground truth: pixel-coverage precision, recall, F per image");
  cmd->add_option("--gt", a->gt, "Folder of ground-truth <name>.txt (x1 y1 x2 y2 per line)")
      ->required();
  cmd->add_option("--est", a->est, "Folder of detected <name>.txt (plucker lines detect --out)")
      ->required();
  cmd->add_option("--threshold", a->threshold, "Coverage distance tau [px]")->capture_default_str();
  cmd->add_flag("--json", a->json, "Print machine-readable JSON instead of a table");
  cmd->callback(
      [a, exit_code] { RunGuarded("eval lines", exit_code, [&] { return RunEvalLines(*a); }); });
}

}  // namespace app
}  // namespace plucker
