// Line matching and tracks on real images, and their quality against ground-truth poses:
//   plucker lines match --image1 A --image2 B CAMERA [--out matches.txt] [--draw out.png]
//   plucker lines track --images DIR CAMERA [--out OUTDIR]
//                       [--gt poses.txt | --gt-cameras DIR] [--gating points|gt|none]
//                       [--reduce 1|2|4|8] [--max-frames N] [--json] [--quiet]
//   plucker eval tracks --segments segments.txt CAMERA
//                       (--gt poses.txt | --gt-cameras DIR) [--reduce R] [--threshold 2]
//                       [--min-views 3] [--json]
// CAMERA: --calib calib.txt|camchain.yaml | --intrinsics K.txt | --sensor sensor.yaml
// (camera_input.h); a distorted camera's images are undistorted into the pinhole of its K before
// anything is detected (segments and points are in that view). Pipeline per frame: detect
// segments (vision/line_detector.h, default method), KLT point tracks with RANSAC
// (vision/point_tracker.h), the fundamental matrix from the point tracks (or from the ground
// truth with --gating gt) for the epipolar gate, then the line tracker (vision/line_tracker.h).
// OUTDIR gets segments.txt and points.txt (io/track_files.h, the rows of the simulator's format).
// With ground truth the track quality (eval/line_tracks.h) is printed: a track of --min-views or
// more views is correct when the line triangulated from the ground-truth cameras reprojects
// within --threshold px of both endpoints of every segment of the track.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "camera_input.h"
#include "commands.h"
#include "overlay.h"
#include "plucker/eval/line_tracks.h"
#include "plucker/io/camera_calibration.h"
#include "plucker/io/image_folder.h"
#include "plucker/io/io_error.h"
#include "plucker/io/track_files.h"
#include "plucker/io/trajectory_io.h"
#include "plucker/vision/line_detector.h"
#include "plucker/vision/line_matcher.h"
#include "plucker/vision/line_tracker.h"
#include "plucker/vision/point_tracker.h"
#include "plucker/vision/undistort.h"
#include "run_guarded.h"

namespace plucker {
namespace app {
namespace {

namespace fs = std::filesystem;

struct CameraArgs {
  CameraFlags flags;
  int reduce = 1;
};

void AddCameraOptions(CLI::App* cmd, CameraArgs* a) {
  AddCameraFlags(cmd, &a->flags, CameraFlagSet{true, false});
  cmd->add_option("--reduce", a->reduce,
                  "Decode the images at 1/R of their size (1, 2, 4 or 8; K is scaled to match)")
      ->capture_default_str();
}

// The images as the detectors see them (camera_input.h's rule): a distorted camera's images
// undistorted into the pinhole of its K first, then reduced; K of the (possibly reduced)
// images. Pixel centres at integers: a reduced pixel i covers the original pixels R i .. R i +
// R - 1, so x_reduced = (x - (R - 1) / 2) / R.
struct LineCamera {
  PinholeIntrinsics K;
  std::optional<vision::Undistorter> undistorter;
  int reduce = 1;

  cv::Mat Read(const std::string& path) const {
    if (!undistorter) return io::ReadGrayImage(path, reduce);
    const cv::Mat ideal = undistorter->Undistort(io::ReadGrayImage(path));
    if (reduce == 1) return ideal;
    cv::Mat out;
    cv::resize(ideal, out, cv::Size(ideal.cols / reduce, ideal.rows / reduce), 0, 0,
               cv::INTER_AREA);
    return out;
  }
};

LineCamera ReadLineCamera(const CameraArgs& a, int width, int height) {
  if (a.reduce != 1 && a.reduce != 2 && a.reduce != 4 && a.reduce != 8) {
    throw std::invalid_argument("--reduce must be 1, 2, 4 or 8");
  }
  // KITTI and Strecha files carry no size (0: no images, nothing checked).
  const CameraCalibration calib = ReadCameraCalibration(a.flags, width, height);
  LineCamera c;
  c.reduce = a.reduce;
  if (width > 0 && NeedsUndistortion(calib.camera, calib.source))
    c.undistorter.emplace(calib.camera);
  c.K = calib.camera.K;
  const double r = a.reduce;
  c.K.fx /= r;
  c.K.fy /= r;
  c.K.cx = (c.K.cx - (r - 1) / 2) / r;
  c.K.cy = (c.K.cy - (r - 1) / 2) / r;
  return c;
}

// Ground-truth poses T_w_c: a KITTI poses file or a folder of Strecha .camera files.
std::vector<SE3d> ReadGroundTruth(const std::string& poses, const std::string& cameras) {
  if (!poses.empty() && !cameras.empty()) {
    throw std::invalid_argument("give at most one of --gt poses.txt or --gt-cameras DIR");
  }
  if (!poses.empty()) return io::ReadTrajectory(poses, io::TrajectoryFormat::kKitti).poses;
  std::vector<SE3d> out;
  for (const std::string& file : io::ListStrechaCameraFiles(cameras)) {
    out.push_back(io::ReadStrechaCamera(file).T_w_c);
  }
  return out;
}

std::string Percent(double x) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f %%", 100.0 * x);
  return buf;
}

nlohmann::json QualityJson(const eval::LineTrackQuality& q, double threshold, int min_views) {
  nlohmann::json per_track = nlohmann::json::array();
  for (const eval::LineTrackResult& r : q.results) {
    if (r.verdict == eval::TrackVerdict::kShort) continue;
    per_track.push_back({{"id", r.line_id},
                         {"views", r.views},
                         {"first", r.first_frame},
                         {"last", r.last_frame},
                         {"verdict", eval::ToString(r.verdict)},
                         {"max_error_px", r.max_error_px}});
  }
  nlohmann::json histogram = nlohmann::json::object();
  for (const auto& [views, count] : q.length_histogram) histogram[std::to_string(views)] = count;
  return {{"threshold_px", threshold},
          {"min_views", min_views},
          {"frames", q.frames},
          {"observations", q.observations},
          {"tracks", q.tracks},
          {"evaluated", q.evaluated},
          {"correct", q.correct},
          {"wrong", q.wrong},
          {"unconstrained", q.unconstrained},
          {"precision", q.precision()},
          {"median_length", q.median_length},
          {"mean_length", q.mean_length},
          {"segments_per_frame", q.segments_per_frame},
          {"length_histogram", histogram},
          {"tracks_judged", per_track}};
}

void PrintQuality(const eval::LineTrackQuality& q, double threshold, int min_views) {
  std::printf("Line tracks vs ground truth (%d+ views, correct within %g px):\n", min_views,
              threshold);
  std::printf("  frames %d, segments %d, tracks %d, with %d+ views %d\n", q.frames, q.observations,
              q.tracks, min_views, q.evaluated);
  std::printf("  correct %d, wrong %d, unconstrained (planes nearly parallel) %d\n", q.correct,
              q.wrong, q.unconstrained);
  std::printf("  precision %s (correct / (correct + wrong))\n", Percent(q.precision()).c_str());
  std::printf(
      "  length of %d+ view tracks: median %.1f, mean %.2f views; %.1f of their segments "
      "per frame\n",
      min_views, q.median_length, q.mean_length, q.segments_per_frame);
  std::vector<double> errors;
  for (const eval::LineTrackResult& r : q.results) {
    if (r.verdict == eval::TrackVerdict::kCorrect || r.verdict == eval::TrackVerdict::kWrong) {
      errors.push_back(r.max_error_px);
    }
  }
  if (!errors.empty()) {
    std::sort(errors.begin(), errors.end());
    auto at = [&](double p) { return errors[static_cast<std::size_t>(p * (errors.size() - 1))]; };
    std::printf(
        "  largest endpoint distance per judged track: median %.2f, 75 %% %.2f, 90 %% %.2f "
        "px\n",
        at(0.5), at(0.75), at(0.9));
  }
  std::printf("  histogram (views: tracks):");
  int more = 0;
  for (const auto& [views, count] : q.length_histogram) {
    if (views <= 10) {
      std::printf(" %d:%d", views, count);
    } else {
      more += count;
    }
  }
  if (more > 0) std::printf(" >10:%d", more);
  std::printf("\n");
}

// ---------------------------------------------------------------------------------------------
// lines track

struct TrackArgs {
  std::string images, out, gt, gt_cameras, gating = "points";
  vision::LineTrackerOptions tracker;
  CameraArgs camera;
  int max_frames = 0;
  double threshold = 2.0;
  int min_views = 3;
  bool json = false, quiet = false;
};

int RunTrack(const TrackArgs& a) {
  const io::ImageFolder folder = io::OpenImageFolder(a.images);
  std::vector<std::string> files = folder.files;
  if (a.max_frames > 0 && static_cast<int>(files.size()) > a.max_frames) files.resize(a.max_frames);
  const LineCamera camera = ReadLineCamera(a.camera, folder.size.width, folder.size.height);
  const PinholeIntrinsics& K = camera.K;
  std::vector<SE3d> gt;
  if (!a.gt.empty() || !a.gt_cameras.empty()) {
    gt = ReadGroundTruth(a.gt, a.gt_cameras);
    if (gt.size() < files.size()) {
      throw io::IoError(
          a.gt.empty() ? a.gt_cameras : a.gt,
          std::to_string(gt.size()) + " poses for " + std::to_string(files.size()) + " images");
    }
  }
  if (a.gating != "points" && a.gating != "gt" && a.gating != "none") {
    throw std::invalid_argument("--gating must be points, gt or none");
  }
  if (a.gating == "gt" && gt.empty()) throw std::invalid_argument("--gating gt needs --gt");
  if (!a.out.empty()) {
    std::error_code ec;
    fs::create_directories(a.out, ec);
    if (!fs::is_directory(a.out, ec)) throw io::IoError(a.out, "cannot create the --out folder");
  }

  vision::PointTracker points(vision::PointTrackerOptions{}, K);
  vision::LineTracker lines(a.tracker);
  std::vector<sensor::SegmentObservation> segment_obs;
  std::vector<sensor::PointObservation> point_obs, previous_points;
  double ms_detect = 0, ms_points = 0, ms_lines = 0;
  int no_lines = 0;
  using Clock = std::chrono::steady_clock;
  auto ms_since = [](Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
  };
  for (std::size_t f = 0; f < files.size(); ++f) {
    const cv::Mat gray = camera.Read(files[f]);
    auto t = Clock::now();
    const vision::LineDetection det = vision::DetectLineSegments(gray);
    ms_detect += ms_since(t);
    t = Clock::now();
    const vision::PointTrackerFrame pf = points.Track(gray);
    ms_points += ms_since(t);
    std::optional<Eigen::Matrix3d> F;
    if (f > 0 && a.gating == "points") {
      F = vision::FundamentalFromPointTracks(previous_points, pf.observations, K);
    } else if (f > 0 && a.gating == "gt") {
      F = vision::FundamentalFromPoses(K, gt[f - 1], gt[f]);
    }
    t = Clock::now();
    const vision::LineTrackerFrame lf = lines.Track(gray, det.segments, F);
    ms_lines += ms_since(t);
    if (det.segments.empty()) {
      ++no_lines;
      std::fflush(stdout);
      std::cerr << "plucker lines track: warning: " << files[f] << ": no line segments\n";
    }
    segment_obs.insert(segment_obs.end(), lf.observations.begin(), lf.observations.end());
    point_obs.insert(point_obs.end(), pf.observations.begin(), pf.observations.end());
    previous_points = pf.observations;
    if (!a.quiet && !a.json) {
      const vision::LineTrackerStats& s = lf.stats;
      std::printf(
          "[%zu/%zu] %s: %zu segments, %d continued, %d re-associated, %d new%s; "
          "%d points\n",
          f + 1, files.size(), fs::path(files[f]).filename().c_str(), lf.observations.size(),
          s.continued, s.reassociated, s.started,
          f == 0 ? "" : (s.epipolar_gate ? " (epipolar gate)" : " (no epipolar gate)"),
          pf.stats.live());
    }
  }
  const std::vector<std::string> header = {
      "plucker lines track --images " + a.images + " --gating " + a.gating,
      std::to_string(files.size()) + " frames, line tracker " +
          std::to_string(lines.next_track_id()) + " tracks"};
  if (!a.out.empty()) {
    io::WriteSegmentTracks((fs::path(a.out) / "segments.txt").string(), segment_obs, header);
    io::WritePointTracks((fs::path(a.out) / "points.txt").string(), point_obs, header);
  }
  const double n = static_cast<double>(files.size());
  nlohmann::json json = {
      {"frames", files.size()},
      {"segments", segment_obs.size()},
      {"tracks", lines.next_track_id()},
      {"point_tracks", points.next_track_id()},
      {"frames_without_lines", no_lines},
      {"ms_per_frame",
       {{"detect", ms_detect / n}, {"points", ms_points / n}, {"lines", ms_lines / n}}}};
  if (!a.json && !a.quiet) {
    std::printf(
        "%zu frames: %zu segments in %d line tracks, %d point tracks; ms per frame: "
        "detect %.1f, points %.1f, describe+track lines %.1f%s\n",
        files.size(), segment_obs.size(), lines.next_track_id(), points.next_track_id(),
        ms_detect / n, ms_points / n, ms_lines / n, a.out.empty() ? "" : (" -> " + a.out).c_str());
  }
  if (!gt.empty()) {
    gt.resize(files.size());
    eval::LineTrackQualityOptions qo;
    qo.max_error_px = a.threshold;
    qo.min_views = a.min_views;
    const eval::LineTrackQuality q = eval::EvaluateLineTracks(K, gt, segment_obs, qo);
    if (a.json) {
      json["quality"] = QualityJson(q, a.threshold, a.min_views);
    } else {
      PrintQuality(q, a.threshold, a.min_views);
    }
  }
  if (a.json) std::cout << json.dump(2) << "\n";
  return 0;
}

// ---------------------------------------------------------------------------------------------
// lines match

struct MatchArgs {
  std::string image1, image2, out, draw;
  CameraArgs camera;
  bool quiet = false;
};

int RunMatch(const MatchArgs& a) {
  if (a.image1.empty() || a.image2.empty()) {
    throw std::invalid_argument("give --image1 and --image2");
  }
  const io::ImageSize size = io::CheckSameImageSize({a.image1, a.image2});
  const LineCamera camera = ReadLineCamera(a.camera, size.width, size.height);
  const PinholeIntrinsics& K = camera.K;
  const cv::Mat g1 = camera.Read(a.image1);
  const cv::Mat g2 = camera.Read(a.image2);
  const auto d1 = vision::DetectLineSegments(g1), d2 = vision::DetectLineSegments(g2);
  for (const auto& [det, name] : {std::make_pair(&d1, &a.image1), std::make_pair(&d2, &a.image2)}) {
    if (det->segments.empty()) {
      std::cerr << "plucker lines match: warning: " << *name << ": no line segments\n";
    }
  }
  vision::PointTracker points(vision::PointTrackerOptions{}, K);
  const auto p1 = points.Track(g1), p2 = points.Track(g2);
  const auto F = vision::FundamentalFromPointTracks(p1.observations, p2.observations, K);
  const vision::LineFeatures f1 = vision::DescribeLines(g1, d1.segments);
  const vision::LineFeatures f2 = vision::DescribeLines(g2, d2.segments);
  const vision::LineMatchResult r = vision::MatchLines(f1, f2, {}, F);
  const vision::LineMatchStats& s = r.stats;
  if (!a.quiet) {
    std::printf("%d and %d described segments; epipolar gate %s (%zu common point tracks)\n", s.a,
                s.b, F ? "on" : "off: no relative pose from the points",
                p2.observations.size() - p2.stats.detected);
    std::printf(
        "pairs %ld: rejected by angle %ld, length %ld, midpoint distance %ld, epipolar "
        "overlap %ld; %ld gated\n",
        s.pairs, s.rejected_angle, s.rejected_length, s.rejected_distance, s.rejected_epipolar,
        s.gated);
    std::printf(
        "segments of image 1: no candidate %d, Hamming %d, ratio %d, not mutual %d; "
        "%d matches\n",
        s.no_candidate, s.rejected_hamming, s.rejected_ratio, s.rejected_mutual, s.matches);
  }
  if (r.matches.empty()) {
    std::cerr << "plucker lines match: warning: " << a.image1 << " / " << a.image2
              << ": no line matches\n";
  }
  if (!a.out.empty()) {
    std::string text = "# plucker lines match --image1 " + a.image1 + " --image2 " + a.image2 +
                       "\n# x1 y1 x2 y2 (image 1)  x1 y1 x2 y2 (image 2)  hamming [px]\n";
    char buf[200];
    for (const vision::LineMatch& m : r.matches) {
      const auto& u = f1.segments[m.a];
      const auto& v = f2.segments[m.b];
      std::snprintf(buf, sizeof(buf), "%.2f %.2f %.2f %.2f %.2f %.2f %.2f %.2f %d\n", u[0], u[1],
                    u[2], u[3], v[0], v[1], v[2], v[3], m.distance);
      text += buf;
    }
    io::WriteFileAtomically(a.out, text);
  }
  if (!a.draw.empty()) {
    cv::Mat canvas;
    cv::vconcat(overlay::Canvas(g1), overlay::Canvas(g2), canvas);
    const Eigen::Vector2d dy(0.0, g1.rows);  // image 2 below image 1
    for (const vision::LineMatch& m : r.matches) {
      const vision::Segment2d& u = f1.segments[m.a];
      const vision::Segment2d& v = f2.segments[m.b];
      const cv::Scalar colour = overlay::TrackColour(m.a);
      overlay::Segment(&canvas, u.head<2>(), u.tail<2>(), colour, 2, 1.0, cv::LINE_8);
      overlay::Segment(&canvas, v.head<2>() + dy, v.tail<2>() + dy, colour, 2, 1.0, cv::LINE_8);
      overlay::Segment(&canvas, 0.5 * (u.head<2>() + u.tail<2>()),
                       0.5 * (v.head<2>() + v.tail<2>()) + dy, colour, 1, 1.0, cv::LINE_8);
    }
    overlay::WriteImage(a.draw, canvas);
  }
  return 0;
}

// ---------------------------------------------------------------------------------------------
// eval tracks

struct EvalTracksArgs {
  std::string segments, gt, gt_cameras;
  CameraArgs camera;
  double threshold = 2.0;
  int min_views = 3;
  bool json = false;
};

int RunEvalTracks(const EvalTracksArgs& a) {
  if (a.segments.empty()) throw std::invalid_argument("give --segments segments.txt");
  if (a.gt.empty() && a.gt_cameras.empty()) {
    throw std::invalid_argument("give --gt poses.txt or --gt-cameras DIR");
  }
  if (!(a.threshold > 0) || a.min_views < 2) {
    throw std::invalid_argument("--threshold must be > 0 and --min-views >= 2");
  }
  const PinholeIntrinsics K = ReadLineCamera(a.camera, 0, 0).K;
  const std::vector<SE3d> gt = ReadGroundTruth(a.gt, a.gt_cameras);
  const std::vector<sensor::SegmentObservation> obs = io::ReadSegmentTracks(a.segments);
  if (obs.empty()) throw io::IoError(a.segments, "no segment observations");
  for (const auto& o : obs) {
    if (o.frame >= static_cast<int>(gt.size())) {
      throw io::IoError(a.segments, "frame " + std::to_string(o.frame) + " but only " +
                                        std::to_string(gt.size()) + " ground-truth poses");
    }
  }
  eval::LineTrackQualityOptions qo;
  qo.max_error_px = a.threshold;
  qo.min_views = a.min_views;
  const eval::LineTrackQuality q = eval::EvaluateLineTracks(K, gt, obs, qo);
  if (a.json) {
    std::cout << QualityJson(q, a.threshold, a.min_views).dump(2) << "\n";
  } else {
    PrintQuality(q, a.threshold, a.min_views);
  }
  return 0;
}

}  // namespace

void AddLinesTrack(CLI::App* lines, int* exit_code) {
  auto m = std::make_shared<MatchArgs>();
  CLI::App* match = lines->add_subcommand(
      "match", "Match the line segments of two images (LBD, mutual NN, geometric gates)");
  match->add_option("--image1", m->image1, "First image")->required();
  match->add_option("--image2", m->image2, "Second image")->required();
  AddCameraOptions(match, &m->camera);
  match->add_option("--out", m->out, "Matches file: both segments and the Hamming distance");
  match->add_option("--draw", m->draw, "Picture of the matches (image 1 above image 2)");
  match->add_flag("--quiet", m->quiet, "No statistics (warnings and errors still print)");
  match->callback(
      [m, exit_code] { RunGuarded("lines match", exit_code, [&] { return RunMatch(*m); }); });

  auto t = std::make_shared<TrackArgs>();
  CLI::App* track = lines->add_subcommand(
      "track", "Line segment tracks (and KLT point tracks) over an image sequence");
  track->add_option("--images", t->images, "Folder: its image files in name order")->required();
  AddCameraOptions(track, &t->camera);
  track->add_option("--out", t->out, "Folder for segments.txt and points.txt");
  track->add_option("--gt", t->gt, "KITTI poses.txt (T_w_c per image): track quality");
  track->add_option("--gt-cameras", t->gt_cameras, "Folder of Strecha .camera files: the same");
  track
      ->add_option("--gating", t->gating,
                   "Epipolar gate from: points (KLT + RANSAC), gt (--gt poses), none")
      ->capture_default_str();
  track->add_option("--max-frames", t->max_frames, "Only the first N images (0: all)");
  track->add_option("--threshold", t->threshold, "Track quality: reprojection limit [px]")
      ->capture_default_str();
  track->add_option("--min-views", t->min_views, "Track quality: shortest evaluated track")
      ->capture_default_str();
  vision::LineTrackerOptions& o = t->tracker;
  track->add_option("--min-length", o.describe.min_length_px, "Shortest tracked segment [px]")
      ->capture_default_str();
  track->add_option("--max-hamming", o.match.max_hamming, "LBD Hamming limit (of 256 bits)")
      ->capture_default_str();
  track->add_option("--ratio", o.match.ratio, "Best / second-best Hamming ratio limit")
      ->capture_default_str();
  track
      ->add_option("--flow-gate", o.match.max_prediction_distance_px,
                   "Median distance of the flow-predicted points from the new line [px]")
      ->capture_default_str();
  track->add_option("--max-lost", o.max_lost_frames, "Frames a track may skip (re-association)")
      ->capture_default_str();
  track->add_flag("--json", t->json, "Summary as JSON");
  track->add_flag("--quiet", t->quiet, "No progress lines (warnings and errors still print)");
  track->callback(
      [t, exit_code] { RunGuarded("lines track", exit_code, [&] { return RunTrack(*t); }); });
}

void RegisterEvalTracks(CLI::App& eval_cmd, int* exit_code) {
  auto a = std::make_shared<EvalTracksArgs>();
  CLI::App* cmd = eval_cmd.add_subcommand(
      "tracks", "Line tracks vs ground-truth poses: precision of 3+ view tracks, lengths");
  cmd->add_option("--segments", a->segments, "segments.txt of `plucker lines track`")->required();
  AddCameraOptions(cmd, &a->camera);
  cmd->add_option("--gt", a->gt, "KITTI poses.txt (T_w_c per frame)");
  cmd->add_option("--gt-cameras", a->gt_cameras, "Folder of Strecha .camera files");
  cmd->add_option("--threshold", a->threshold, "Reprojection limit [px]")->capture_default_str();
  cmd->add_option("--min-views", a->min_views, "Shortest evaluated track")->capture_default_str();
  cmd->add_flag("--json", a->json, "Output as JSON");
  cmd->callback(
      [a, exit_code] { RunGuarded("eval tracks", exit_code, [&] { return RunEvalTracks(*a); }); });
}

}  // namespace app
}  // namespace plucker
