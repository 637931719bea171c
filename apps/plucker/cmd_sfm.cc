// plucker sfm: incremental reconstruction of a folder of calibrated images with points and lines
// (src/plucker/sfm/incremental_reconstruction.h). The app reads the images and the calibration,
// extracts the features of each image, runs the reconstruction, times every stage and writes
//   OUTDIR/poses.txt    KITTI, one T_w_c per image in name order (12 `nan` when unregistered)
//   OUTDIR/points.ply   3D points;  OUTDIR/lines.ply  3D segments (vertex pairs + edges)
//   OUTDIR/report.json  views, registration status, tracks, reprojection errors, time per stage
//   OUTDIR/overlay_<image>.png  detected (blue), matched (green) and reprojected (red) segments
// With --gt (Strecha cameras) report.json also holds the track quality against the ground truth:
// every final point and line track triangulated from the ground-truth cameras, and the share that
// reprojects within 1 and 2 px of all its observations (eval/line_tracks.h for the lines).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "camera_input.h"
#include "commands.h"
#include "overlay.h"
#include "plucker/eval/line_tracks.h"
#include "plucker/eval/point_tracks.h"
#include "plucker/geometry/point_projection.h"
#include "plucker/io/camera_calibration.h"
#include "plucker/io/image_folder.h"
#include "plucker/io/io_error.h"
#include "plucker/io/ply.h"
#include "plucker/io/trajectory_io.h"
#include "plucker/sfm/incremental_reconstruction.h"
#include "plucker/vision/undistort.h"
#include "run_guarded.h"
#include "stage_clock.h"

namespace plucker {
namespace app {
namespace {

namespace fs = std::filesystem;

struct SfmArgs {
  std::string images, out, gt;
  CameraFlags camera;
  bool no_lines = false;
  bool refine_segments = false;
  int max_points = 0;
  int detect_size = 1536;
  int max_keypoints = 8000;
  int overlays = 3;
  double line_sigma = 2.0;
  int point_seed = 0;
  int threads = 0;
  bool quiet = false;
};

constexpr const char* kMarker = "plucker sfm";

// OUTDIR must be absent, empty, or a previous output of this command (its report.json says so).
void CheckOutputFolder(const std::string& out) {
  if (!fs::exists(out)) return;
  if (!fs::is_directory(out)) throw io::IoError(out, "exists and is not a folder");
  if (fs::is_empty(out)) return;
  std::ifstream in(fs::path(out) / "report.json");
  nlohmann::json j;
  try {
    if (in) j = nlohmann::json::parse(in);
  } catch (const std::exception&) {
  }
  if (!j.is_object() || j.value("command", "") != kMarker) {
    throw io::IoError(out,
                      "is not empty and not a previous `plucker sfm` output; refusing to "
                      "overwrite it (give another --out)");
  }
}

struct Calibration {
  sensor::Camera camera;  // as read (may be distorted)
  std::optional<vision::Undistorter> undistorter;
};

// The calibration of the images (camera_input.h: the flags and the undistortion rule).
Calibration ReadCalibration(const SfmArgs& a, int width, int height) {
  Calibration c;
  const CameraCalibration calib = ReadCameraCalibration(a.camera, width, height);
  c.camera = calib.camera;
  if (NeedsUndistortion(c.camera, calib.source)) c.undistorter.emplace(c.camera);
  return c;
}

std::string Fixed(double x, int digits = 2) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << x;
  return s.str();
}

// Detected segments (blue), segments of reconstructed lines (green) and the reprojected 3D
// segments (red), drawn on the image reduced to a longer side of at most 1536 px.
void WriteOverlay(const std::string& path, const cv::Mat& gray, const sfm::ViewFeatures& f,
                  int view, const PinholeIntrinsics& K, const SE3d& T_w_c,
                  const std::vector<sfm::SfmLine>& lines) {
  const double s = std::min(1.0, 1536.0 / std::max(gray.cols, gray.rows));
  cv::Mat canvas = overlay::Canvas(gray, s);
  for (const vision::Segment2d& seg : f.lines.segments)
    overlay::Segment(&canvas, seg.head<2>(), seg.tail<2>(), overlay::kDetectedSegment, 1, s);
  for (const sfm::SfmLine& l : lines) {
    for (const auto& [v, i] : l.observations) {
      if (v != view) continue;
      const vision::Segment2d& seg = f.lines.segments[i];
      overlay::Segment(&canvas, seg.head<2>(), seg.tail<2>(), overlay::kReconstructedSegment, 2, s);
      const auto a = ProjectPoint(K, T_w_c, l.start_w), b = ProjectPoint(K, T_w_c, l.end_w);
      if (a && b) overlay::Segment(&canvas, *a, *b, overlay::kReprojected, 1, s);
    }
  }
  overlay::WriteImage(path, canvas);
}

struct Loaded {
  std::vector<std::string> files;
  std::vector<cv::Mat> images;       // empty when skipped
  std::vector<std::string> skipped;  // "file: reason"
  io::ImageSize size;
};

// Reads every image; an unreadable one or one of another size than the first readable image is
// skipped (named). Throws IoError when fewer than two images remain.
Loaded LoadImages(const std::string& dir) {
  Loaded l;
  l.files = io::ListImageFiles(dir);
  for (const std::string& file : l.files) {
    cv::Mat image;
    try {
      image = io::ReadGrayImage(file);
    } catch (const io::IoError& e) {
      l.skipped.push_back(e.what());
      l.images.emplace_back();
      continue;
    }
    if (l.size.width == 0) l.size = {image.cols, image.rows};
    if (image.cols != l.size.width || image.rows != l.size.height) {
      l.skipped.push_back(file + ": size " + std::to_string(image.cols) + "x" +
                          std::to_string(image.rows) + " differs from the first image's " +
                          std::to_string(l.size.width) + "x" + std::to_string(l.size.height));
      image.release();
    }
    l.images.push_back(image);
  }
  const long readable =
      std::count_if(l.images.begin(), l.images.end(), [](const cv::Mat& m) { return !m.empty(); });
  if (readable < 2) {
    throw io::IoError(
        dir, "needs at least 2 readable images of one size, has " + std::to_string(readable));
  }
  return l;
}

// Track quality against ground-truth cameras (--gt): each final track triangulated from them;
// the share of tracks whose largest reprojection error (point: pixel distance; line: endpoint to
// the reprojected line) is within 1 and within 2 px. Lines whose viewing planes are nearly
// parallel cannot be judged that way (eval/line_tracks.h) and are counted apart.
nlohmann::json GroundTruthTrackQuality(const PinholeIntrinsics& K, const std::vector<SE3d>& gt,
                                       const std::vector<sfm::ViewFeatures>& views,
                                       const sfm::SfmResult& r) {
  std::vector<sensor::PointObservation> point_observations;
  for (std::size_t p = 0; p < r.points.size(); ++p) {
    for (const auto& [v, k] : r.points[p].observations)
      point_observations.push_back({v, static_cast<int>(p), views[v].keypoints[k]});
  }
  const eval::PointTrackQuality pq = eval::EvaluatePointTracks(K, gt, point_observations);
  int points = 0, points_1px = 0, points_2px = 0;
  for (const eval::PointTrackResult& t : pq.results) {
    if (!t.judged) continue;
    ++points;
    points_1px += t.max_error_px <= 1.0;
    points_2px += t.max_error_px <= 2.0;
  }
  std::vector<sensor::SegmentObservation> observations;
  for (std::size_t l = 0; l < r.lines.size(); ++l) {
    for (const auto& [v, k] : r.lines[l].observations) {
      const vision::Segment2d& s = views[v].lines.segments[k];
      observations.push_back({v, static_cast<int>(l), s.head<2>(), s.tail<2>()});
    }
  }
  eval::LineTrackQualityOptions lo;
  lo.min_views = 2;
  const eval::LineTrackQuality q = eval::EvaluateLineTracks(K, gt, observations, lo);
  int lines = 0, lines_1px = 0, lines_2px = 0;
  for (const eval::LineTrackResult& t : q.results) {
    if (t.verdict != eval::TrackVerdict::kCorrect && t.verdict != eval::TrackVerdict::kWrong)
      continue;
    ++lines;
    lines_1px += t.max_error_px <= 1.0;
    lines_2px += t.max_error_px <= 2.0;
  }
  const auto share = [](int k, int n) { return n > 0 ? static_cast<double>(k) / n : 0.0; };
  return {{"points_judged", points},
          {"points_within_1px", share(points_1px, points)},
          {"points_within_2px", share(points_2px, points)},
          {"lines_judged", lines},
          {"lines_unconstrained", q.unconstrained},
          {"lines_within_1px", share(lines_1px, lines)},
          {"lines_within_2px", share(lines_2px, lines)}};
}

int Run(const SfmArgs& a) {
  const double t_start = WallMs();
  const auto say = [&](const std::string& m) {
    if (!a.quiet) std::cerr << "plucker sfm: " << m << "\n";
  };
  CheckOutputFolder(a.out);
  if (a.max_points < 0) throw std::invalid_argument("--max-points must be >= 0");
  Loaded in = LoadImages(a.images);
  for (const std::string& s : in.skipped)
    std::cerr << "plucker sfm: warning: skipped " << s << "\n";
  Calibration calib = ReadCalibration(a, in.size.width, in.size.height);
  const PinholeIntrinsics K =
      calib.undistorter ? calib.undistorter->ideal_camera().K : calib.camera.K;
  std::vector<SE3d> gt;  // --gt: read first, so that a bad folder fails before the work
  if (!a.gt.empty()) {
    const std::string dir =
        fs::is_directory(fs::path(a.gt) / "cameras") ? (fs::path(a.gt) / "cameras").string() : a.gt;
    for (const std::string& file : io::ListStrechaCameraFiles(dir))
      gt.push_back(io::ReadStrechaCamera(file).T_w_c);
    if (gt.size() != in.files.size()) {
      throw io::IoError(dir, std::to_string(gt.size()) + " cameras for " +
                                 std::to_string(in.files.size()) + " images");
    }
  }
  const double read_ms = WallMs() - t_start;

  // Features.
  sfm::FeatureOptions fo;
  fo.detection_max_side = a.detect_size;
  fo.max_keypoints = a.max_keypoints;
  fo.detect_lines = !a.no_lines;
  fo.line_detector.refine = a.refine_segments;
  const int n = static_cast<int>(in.files.size());
  std::vector<sfm::ViewFeatures> views(n);
  const double t_features = WallMs();
  for (int i = 0; i < n; ++i) {
    if (in.images[i].empty()) continue;
    if (calib.undistorter) in.images[i] = calib.undistorter->Undistort(in.images[i]);
    const double t0 = WallMs();
    views[i] = sfm::ExtractFeatures(in.images[i], fo);
    say("features " + std::to_string(i + 1) + "/" + std::to_string(n) + " " +
        fs::path(in.files[i]).filename().string() + ": " +
        std::to_string(views[i].keypoints.size()) + " keypoints, " +
        std::to_string(views[i].lines.size()) + " segments (" + Fixed((WallMs() - t0) / 1e3, 1) +
        " s)");
    if (views[i].keypoints.empty()) {
      std::cerr << "plucker sfm: warning: " << in.files[i]
                << ": no keypoints (no texture?); the view is skipped\n";
    }
  }
  const double features_ms = WallMs() - t_features;

  // Reconstruction.
  sfm::SfmOptions so;
  so.use_lines = !a.no_lines;
  so.max_points = a.max_points;
  so.line_sigma_px = a.line_sigma;
  so.point_subset_seed = a.point_seed;
  so.num_threads = a.threads > 0
                       ? a.threads
                       : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  BasicStageClock<sfm::SfmStage, sfm::kNumSfmStages> clock(/*wall=*/true);
  const sfm::SfmResult r = sfm::Reconstruct(K, views, so, clock.Observer(), say);
  if (!r.ok) throw io::IoError(a.images, "reconstruction failed: " + r.message);

  // Outputs.
  const double t_write = WallMs();
  fs::create_directories(a.out);
  io::WriteKittiPosesWithGaps((fs::path(a.out) / "poses.txt").string(), r.T_w_c);
  std::vector<Eigen::Vector3d> points;
  for (const sfm::SfmPoint& p : r.points) points.push_back(p.p_w);
  io::WritePly((fs::path(a.out) / "points.ply").string(), points);
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments;
  for (const sfm::SfmLine& l : r.lines) segments.emplace_back(l.start_w, l.end_w);
  io::WriteSegmentsPly((fs::path(a.out) / "lines.ply").string(), segments);
  std::vector<int> registered;
  for (int i = 0; i < n; ++i)
    if (r.T_w_c[i]) registered.push_back(i);
  nlohmann::json overlays = nlohmann::json::array();
  if (!a.no_lines && a.overlays > 0 && !registered.empty()) {
    const int m = std::min<int>(a.overlays, registered.size());
    for (int k = 0; k < m; ++k) {
      const int i = registered[m == 1 ? 0 : k * (registered.size() - 1) / (m - 1)];
      const std::string name = "overlay_" + fs::path(in.files[i]).stem().string() + ".png";
      WriteOverlay((fs::path(a.out) / name).string(), in.images[i], views[i], i, K, *r.T_w_c[i],
                   r.lines);
      overlays.push_back(name);
    }
  }
  const double write_ms = WallMs() - t_write;
  const double total_ms = WallMs() - t_start;

  nlohmann::json per_view = nlohmann::json::array();
  nlohmann::json unregistered = nlohmann::json::array();
  for (int i = 0; i < n; ++i) {
    per_view.push_back({{"image", fs::path(in.files[i]).filename().string()},
                        {"registered", r.T_w_c[i].has_value()},
                        {"status", r.view_status[i]},
                        {"keypoints", views[i].keypoints.size()},
                        {"segments", views[i].lines.size()}});
    if (!r.T_w_c[i]) unregistered.push_back(fs::path(in.files[i]).filename().string());
  }
  nlohmann::json stages = {{"read", read_ms}, {"features", features_ms}};
  for (int s = 0; s < sfm::kNumSfmStages; ++s)
    stages[sfm::ToString(static_cast<sfm::SfmStage>(s))] = clock.ms(s);
  stages["write"] = write_ms;
  stages["total"] = total_ms;
  const sfm::SfmStatistics& st = r.stats;
  nlohmann::json report = {{"command", kMarker},
                           {"images", a.images},
                           {"lines", !a.no_lines},
                           {"max_points", a.max_points},
                           {"point_seed", a.point_seed},
                           {"detect_size", a.detect_size},
                           {"line_sigma_px", a.line_sigma},
                           {"refine_segments", a.refine_segments},
                           {"views", st.views},
                           {"registered", st.registered},
                           {"unregistered", unregistered},
                           {"skipped", in.skipped},
                           {"verified_pairs", st.verified_pairs},
                           {"initial_pair", {st.init_a, st.init_b}},
                           {"point_tracks", st.point_tracks},
                           {"points", st.points},
                           {"lines_3d", st.lines},
                           {"point_observations", st.point_observations},
                           {"line_observations", st.line_observations},
                           {"mean_point_error_px", st.mean_point_error_px},
                           {"mean_line_error_px", st.mean_line_error_px},
                           {"rejected_point_observations", st.rejected_point_observations},
                           {"rejected_line_observations", st.rejected_line_observations},
                           {"adjustments", st.adjustments},
                           {"line_refined_registrations", st.line_refined_registrations},
                           {"overlays", overlays},
                           {"time_ms", stages},
                           {"per_view", per_view}};
  if (!gt.empty()) report["ground_truth_tracks"] = GroundTruthTrackQuality(K, gt, views, r);
  io::WriteFileAtomically((fs::path(a.out) / "report.json").string(), report.dump(2) + "\n");

  if (!a.quiet) {
    std::printf("%-28s %s\n", "views", std::to_string(st.views).c_str());
    std::printf("%-28s %d\n", "registered", st.registered);
    for (const auto& u : unregistered)
      std::printf("%-28s %s\n", "  unregistered", u.get<std::string>().c_str());
    std::printf("%-28s %d (of %d tracks)\n", "points", st.points, st.point_tracks);
    std::printf("%-28s %d\n", "lines", st.lines);
    std::printf("%-28s %.3f px\n", "point reprojection error", st.mean_point_error_px);
    std::printf("%-28s %.3f px\n", "line reprojection error", st.mean_line_error_px);
    if (report.contains("ground_truth_tracks")) {
      const nlohmann::json& g = report["ground_truth_tracks"];
      std::printf("%-28s points %.1f %% / %.1f %%, lines %.1f %% / %.1f %% (%d judged)\n",
                  "gt tracks within 1 / 2 px", 100.0 * g["points_within_1px"].get<double>(),
                  100.0 * g["points_within_2px"].get<double>(),
                  100.0 * g["lines_within_1px"].get<double>(),
                  100.0 * g["lines_within_2px"].get<double>(), g["lines_judged"].get<int>());
    }
    for (const auto& [k, v] : stages.items())
      std::printf("time %-23s %.1f s\n", k.c_str(), v.get<double>() / 1e3);
    std::printf("output in %s\n", a.out.c_str());
  }
  return 0;
}

}  // namespace

void RegisterSfm(CLI::App& app, int* exit_code) {
  auto a = std::make_shared<SfmArgs>();
  CLI::App* cmd = app.add_subcommand(
      "sfm",
      "Reconstruct cameras, 3D points and 3D line segments from a folder of calibrated images");
  cmd->add_option("--images", a->images, "Folder of images (image files in name order)")
      ->required();
  AddCameraFlags(cmd, &a->camera, CameraFlagSet{true, false});
  cmd->add_option("--out", a->out, "Output folder")->required();
  cmd->add_flag("--no-lines", a->no_lines, "Points only");
  cmd->add_flag("--refine-segments", a->refine_segments,
                "Re-fit each segment to the sub-pixel gradient maxima across it");
  cmd->add_option("--gt", a->gt,
                  "Strecha cameras (folder of *.camera, or its parent): report the share of "
                  "tracks that reproject within 1 / 2 px from the ground-truth cameras");
  cmd->add_option("--max-points", a->max_points, "Use at most N point tracks (0: all)")
      ->capture_default_str();
  cmd->add_option("--point-seed", a->point_seed,
                  "With --max-points: keep a random subset of the point tracks drawn with this "
                  "seed (> 0; the same subset with or without lines) instead of the longest")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--threads", a->threads,
                  "Threads for the matching (0: every core; the result does not depend on it)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--detect-size", a->detect_size,
                  "SIFT runs on images reduced to this longer side [px] (0: full size)")
      ->capture_default_str();
  cmd->add_option("--max-keypoints", a->max_keypoints, "SIFT keypoints per image")
      ->capture_default_str();
  cmd->add_option("--line-sigma", a->line_sigma,
                  "Standard deviation of the line endpoint distances in the adjustment [px] "
                  "(points: 1)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--overlays", a->overlays, "Overlay images to write")->capture_default_str();
  cmd->add_flag("--quiet", a->quiet, "No progress lines and no closing table");
  cmd->callback([a, exit_code]() { RunGuarded("sfm", exit_code, [&] { return Run(*a); }); });
}

}  // namespace app
}  // namespace plucker
