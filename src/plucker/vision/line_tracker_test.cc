#include "plucker/vision/line_tracker.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <random>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "plucker/eval/line_tracks.h"
#include "plucker/geometry/line_triangulation.h"
#include "plucker/io/camera_calibration.h"
#include "plucker/io/image_folder.h"
#include "plucker/io/trajectory_io.h"
#include "plucker/vision/point_tracker.h"
#include "plucker/vision/vision_test_utils.h"

// OpenCV 4.6's EdgeDrawing (the line detector) leaks ~32 bytes per detector inside
// libopencv_ximgproc; only that module is suppressed (as in line_detector_test.cc).
extern "C" const char* __lsan_default_suppressions() { return "leak:libopencv_ximgproc\n"; }

namespace plucker {
namespace vision {
namespace {

namespace fs = std::filesystem;

cv::Mat Scene(int width, int height, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> g(0, 255), noise(-12, 12);
  cv::Mat image(height, width, CV_8UC1);
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c)
      image.at<uchar>(r, c) = cv::saturate_cast<uchar>(128 + noise(rng));
  }
  std::uniform_real_distribution<double> x(0.1 * width, 0.9 * width), y(0.1 * height, 0.9 * height);
  std::uniform_real_distribution<double> size(25, 60);
  for (int i = 0; i < 12; ++i) {
    const double cx = x(rng), cy = y(rng), w = size(rng), h = size(rng);
    cv::rectangle(image, cv::Rect(cvRound(cx - w / 2), cvRound(cy - h / 2), cvRound(w), cvRound(h)),
                  cv::Scalar(g(rng)), -1);
  }
  cv::GaussianBlur(image, image, cv::Size(3, 3), 0.7);
  return image;
}

using testing::Shifted;

fs::path KittiClipDir() { return fs::path(PLUCKER_SHARED_DATA_DIR) / "kitti-mono-clip"; }

struct KittiClip {
  io::ImageFolder folder;
  PinholeIntrinsics K;
  io::Trajectory gt;
};

// The shared KITTI clip's images, pinhole and ground truth; nullopt when the data is absent.
std::optional<KittiClip> OpenKittiClip() {
  const fs::path data = KittiClipDir();
  if (!fs::exists(data / "poses.txt")) return std::nullopt;
  KittiClip c;
  c.folder = io::OpenImageFolder((data / "image_0").string());
  c.K = io::ReadKittiCalibration((data / "calib.txt").string(), c.folder.size.width,
                                 c.folder.size.height)
            .camera.K;
  c.gt = io::ReadTrajectory((data / "poses.txt").string());
  return c;
}

double LineDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& s, const Eigen::Vector2d& e) {
  const Eigen::Vector2d d = (e - s).normalized();
  return std::abs(d.x() * (p.y() - s.y()) - d.y() * (p.x() - s.x()));
}

// A shifting image: tracks keep their ids and stay on their edge; a frame without segments is
// skipped and its tracks are re-associated in the next frame.
TEST(LineTracker, StableIdsAndReassociationAfterAMissedFrame) {
  const cv::Mat base = Scene(360, 260, 9);
  LineTracker tracker;
  std::map<int, sensor::SegmentObservation> first;
  const auto f0 = tracker.Track(base, DetectLineSegments(base).segments);
  for (const auto& o : f0.observations) first[o.line_id] = o;
  ASSERT_GT(first.size(), 20u);
  EXPECT_EQ(f0.stats.started, static_cast<int>(first.size()));
  int checked = 0, on_edge = 0, reassociated = 0;
  for (int k = 1; k <= 5; ++k) {
    const Eigen::Vector2d shift(2.5 * k, 1.0 * k);
    const cv::Mat image = Shifted(base, shift.x(), shift.y());
    // Frame 3 has no segments (a detector failure): every track is lost for one frame.
    const std::vector<Segment2d> segments =
        k == 3 ? std::vector<Segment2d>{} : DetectLineSegments(image).segments;
    const LineTrackerFrame f = tracker.Track(image, segments);
    EXPECT_EQ(f.frame, k);
    if (k == 3) {
      EXPECT_TRUE(f.observations.empty());
      EXPECT_GT(f.stats.lost, 10);
      continue;
    }
    if (k == 4) {
      EXPECT_EQ(f.stats.continued, 0);
      EXPECT_GT(f.stats.reassociated, 10);
      reassociated = f.stats.reassociated;
    } else {
      EXPECT_GT(f.stats.continued, 10);
    }
    for (const auto& o : f.observations) {
      EXPECT_EQ(o.frame, k);
      const auto it = first.find(o.line_id);
      if (it == first.end()) continue;
      ++checked;
      on_edge += LineDistance(it->second.s_px + shift, o.s_px, o.e_px) < 1.5 &&
                 LineDistance(it->second.e_px + shift, o.s_px, o.e_px) < 1.5;
    }
  }
  EXPECT_GT(reassociated, 10);
  EXPECT_GT(checked, 60);
  EXPECT_GE(on_edge, 0.95 * checked) << on_edge << " of " << checked;
}

TEST(LineTracker, BadInput) {
  LineTracker tracker;
  EXPECT_THROW(tracker.Track(cv::Mat(), {}), std::invalid_argument);
  EXPECT_THROW(tracker.Track(cv::Mat(20, 20, CV_8UC3), {}), std::invalid_argument);
  const cv::Mat blank(40, 50, CV_8UC1, cv::Scalar(9));
  EXPECT_TRUE(tracker.Track(blank, {}).observations.empty());  // no lines: fine
  EXPECT_TRUE(tracker.Track(blank, {}).observations.empty());
  EXPECT_THROW(tracker.Track(cv::Mat(41, 50, CV_8UC1, cv::Scalar(9)), {}), std::invalid_argument);
  LineTrackerOptions bad;
  bad.max_lost_frames = -1;
  EXPECT_THROW(LineTracker{bad}, std::invalid_argument);
}

// The first frames of the real KITTI clip: tracks of 3+ views against the ground-truth poses
// (the whole clip: `plucker lines track`, docs/results/lines.md).
TEST(LineTracker, RealKittiClipFirstFrames) {
  const std::optional<KittiClip> clip = OpenKittiClip();
  if (!clip) GTEST_SKIP() << "shared data absent: " << KittiClipDir();
  const io::ImageFolder& folder = clip->folder;
  const PinholeIntrinsics& K = clip->K;
  const io::Trajectory& gt = clip->gt;
  const int frames = 6;
  PointTracker points(PointTrackerOptions{}, K);
  LineTracker lines;
  std::vector<sensor::SegmentObservation> obs;
  std::vector<sensor::PointObservation> previous;
  int gated = 0;
  for (int f = 0; f < frames; ++f) {
    const cv::Mat gray = io::ReadGrayImage(folder.files[f]);
    const auto p = points.Track(gray);
    const auto F = f > 0 ? FundamentalFromPointTracks(previous, p.observations, K) : std::nullopt;
    gated += F.has_value();
    const auto l = lines.Track(gray, DetectLineSegments(gray).segments, F);
    obs.insert(obs.end(), l.observations.begin(), l.observations.end());
    previous = p.observations;
  }
  EXPECT_EQ(gated, frames - 1);
  const eval::LineTrackQuality q = eval::EvaluateLineTracks(K, gt.poses, obs);
  std::printf(
      "KITTI clip, %d frames: %d segments, %d tracks, %d of 3+ views: correct %d, wrong %d, "
      "unconstrained %d, precision %.3f\n",
      frames, q.observations, q.tracks, q.evaluated, q.correct, q.wrong, q.unconstrained,
      q.precision());
  EXPECT_GT(q.correct + q.wrong, 100);
  EXPECT_GE(q.precision(), 0.9);

  // N-view triangulation on these real tracks: the refinement never increases the endpoint
  // distances of the linear solution, and lowers them on average.
  std::map<int, std::vector<LineObservation>> tracks;
  for (const auto& o : obs) tracks[o.line_id].push_back({gt.poses[o.frame], o.s_px, o.e_px});
  int compared = 0, rejected = 0;
  double linear_rms = 0.0, refined_rms = 0.0;
  for (const auto& [id, views] : tracks) {
    if (views.size() < 3) continue;
    const LineTriangulationResult lin = TriangulateLine(K, views);
    const LineTriangulationResult ref = TriangulateLineRefined(K, views);
    rejected += ref.status == LineTriangulationStatus::kSmallParallax;
    if (!lin.ok() || !ref.ok()) continue;
    EXPECT_LE(ref.rms_error_px, lin.rms_error_px + 1e-9);
    linear_rms += lin.rms_error_px;
    refined_rms += ref.rms_error_px;
    ++compared;
  }
  std::printf(
      "real tracks: %d triangulated, mean endpoint RMS linear %.3f px, refined %.3f px; "
      "%d rejected (planes within 2 deg)\n",
      compared, linear_rms / compared, refined_rms / compared, rejected);
  EXPECT_GT(compared, 100);
  EXPECT_GT(rejected, 10);  // forward motion: lines along the road
  EXPECT_LT(refined_rms, linear_rms);
}

// Flow-first association against descriptors on every gated pair, on the same real frames: the
// unique flow-gated pairs skip LBD, which is then computed for a fraction of the segments, and
// the tracks stay as precise.
TEST(LineTracker, FlowFirstDescribesFewerSegmentsOnTheKittiClip) {
  const std::optional<KittiClip> clip = OpenKittiClip();
  if (!clip) GTEST_SKIP() << "shared data absent: " << KittiClipDir();
  const io::ImageFolder& folder = clip->folder;
  const PinholeIntrinsics& K = clip->K;
  const io::Trajectory& gt = clip->gt;
  std::vector<cv::Mat> images;
  std::vector<std::vector<Segment2d>> segments;
  for (int f = 0; f < 4; ++f) {  // the 80 longest segments (apps keep the 60 longest)
    images.push_back(io::ReadGrayImage(folder.files[f]));
    std::vector<Segment2d> s = DetectLineSegments(images.back()).segments;
    std::sort(s.begin(), s.end(), [](const Segment2d& a, const Segment2d& b) {
      return (a.tail<2>() - a.head<2>()).norm() > (b.tail<2>() - b.head<2>()).norm();
    });
    s.resize(std::min<std::size_t>(s.size(), 80));
    segments.push_back(s);
  }
  struct Run {
    int described = 0, flow_matched = 0, segments = 0, continued = 0;
    eval::LineTrackQuality quality;
  };
  auto run = [&](bool flow_first) {
    LineTrackerOptions options;
    options.flow_first = flow_first;
    PointTrackerOptions point_options;
    point_options.target_count = 200;  // as the apps
    PointTracker points(point_options, K);
    LineTracker lines(options);
    Run r;
    std::vector<sensor::SegmentObservation> obs;
    for (std::size_t f = 0; f < images.size(); ++f) {
      const FlowPyramid pyramid(images[f], 15, 4);
      const PointTrackerFrame p = points.Track(pyramid);
      const LineTrackerFrame l = lines.Track(pyramid, segments[f], p.F_cur_prev);
      r.described += l.stats.lbd_described;
      r.flow_matched += l.stats.flow_matched;
      r.segments += l.stats.description.described;
      r.continued += l.stats.continued + l.stats.reassociated;
      EXPECT_EQ(l.stats.match.matches, l.stats.continued + l.stats.reassociated);
      obs.insert(obs.end(), l.observations.begin(), l.observations.end());
    }
    r.quality = eval::EvaluateLineTracks(K, gt.poses, obs);
    return r;
  };
  const Run all = run(false), first = run(true);
  std::printf(
      "descriptors on every gated pair: %d LBD of %d segments, %d continued, precision %.3f; "
      "flow first: %d LBD, %d matched by flow, %d continued, precision %.3f\n",
      all.described, all.segments, all.continued, all.quality.precision(), first.described,
      first.flow_matched, first.continued, first.quality.precision());
  EXPECT_EQ(all.flow_matched, 0);
  EXPECT_GT(first.flow_matched, all.continued / 3);
  EXPECT_LT(first.described, 0.75 * all.described);
  EXPECT_GT(first.continued, 0.9 * all.continued);
  EXPECT_GE(first.quality.precision(), 0.9);
  EXPECT_GE(all.quality.precision(), 0.9);
}

}  // namespace
}  // namespace vision
}  // namespace plucker
