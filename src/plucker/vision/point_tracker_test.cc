#include "plucker/vision/point_tracker.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <random>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "plucker/geometry/point_triangulation.h"
#include "plucker/io/camera_calibration.h"
#include "plucker/io/image_folder.h"
#include "plucker/io/trajectory_io.h"
#include "plucker/vision/vision_test_utils.h"

namespace plucker {
namespace vision {
namespace {

namespace fs = std::filesystem;

using testing::Shifted;
using testing::Texture;

// detect_below_share: frames whose survivors reach the share get no new corners (the corner
// response is not computed); below it the tracker refills to the target as before.
TEST(PointTracker, DetectsOnlyBelowTheShareOfTheTarget) {
  const cv::Mat base = Texture(320, 240, 7);
  PointTrackerOptions options;
  options.target_count = 150;
  options.detect_below_share = 0.5;
  PointTracker tracker(options);
  const PointTrackerFrame first = tracker.Track(base);
  EXPECT_TRUE(first.stats.detection_run);
  EXPECT_EQ(first.stats.detected, 150);
  // A small shift keeps most tracks: no detection although some are missing.
  const PointTrackerFrame kept = tracker.Track(Shifted(base, 2.3, -1.1));
  EXPECT_GT(kept.stats.tracked, 75);
  EXPECT_LT(kept.stats.tracked, 150);  // some left the image: the default would refill
  EXPECT_FALSE(kept.stats.detection_run);
  EXPECT_EQ(kept.stats.detected, 0);
  EXPECT_EQ(kept.stats.live(), kept.stats.tracked);
  // Another texture: every track is lost, the share is not reached, the target is refilled.
  const PointTrackerFrame lost = tracker.Track(Texture(320, 240, 99));
  EXPECT_LT(lost.stats.tracked, 75);
  EXPECT_TRUE(lost.stats.detection_run);
  EXPECT_EQ(lost.stats.live(), 150);
  options.detect_below_share = 0.0;
  EXPECT_THROW(PointTracker{options}, std::invalid_argument);
  options.detect_below_share = 1.5;
  EXPECT_THROW(PointTracker{options}, std::invalid_argument);
}

TEST(PointTracker, FollowsAShiftingImageWithStableIds) {
  const cv::Mat base = Texture(320, 240, 7);
  PointTrackerOptions options;
  options.target_count = 150;
  PointTracker tracker(options);  // no K: fundamental-matrix RANSAC
  const PointTrackerFrame first = tracker.Track(base);
  EXPECT_EQ(first.stats.detected, 150);
  EXPECT_EQ(first.stats.tracked, 0);
  std::map<int, Eigen::Vector2d> start;
  for (const auto& o : first.observations) start[o.point_id] = o.uv;

  int checked = 0, detected_later = 0;
  double max_error = 0;
  for (int k = 1; k <= 4; ++k) {
    const Eigen::Vector2d shift(2.3 * k, -1.1 * k);
    const PointTrackerFrame f = tracker.Track(Shifted(base, shift.x(), shift.y()));
    EXPECT_EQ(f.frame, k);
    EXPECT_EQ(f.stats.live(), 150);  // re-detection refills to the target
    EXPECT_GT(f.stats.tracked, 120);
    EXPECT_TRUE(f.stats.ransac_run);
    EXPECT_EQ(f.stats.ransac_inliers, f.stats.tracked);
    // The RANSAC model is returned: the tracked points satisfy x_cur^T F x_prev = 0.
    ASSERT_TRUE(f.F_cur_prev.has_value());
    EXPECT_NEAR(f.F_cur_prev->norm(), 1.0, 1e-9);
    for (const auto& o : f.observations) {
      const auto it = start.find(o.point_id);
      if (it == start.end() || k != 1) continue;
      const Eigen::Vector3d l = *f.F_cur_prev * it->second.homogeneous();
      EXPECT_LT(std::abs(l.dot(o.uv.homogeneous())) / l.head<2>().norm(), 2.0);
    }
    detected_later += f.stats.detected;
    for (const auto& o : f.observations) {
      const auto it = start.find(o.point_id);
      if (it == start.end()) continue;  // detected after the first frame
      max_error = std::max(max_error, (o.uv - it->second - shift).norm());
      ++checked;
    }
  }
  EXPECT_GT(checked, 400);
  EXPECT_LT(max_error, 0.3);  // after 4 frames of frame-to-frame tracking (measured 0.22)
  EXPECT_EQ(tracker.next_track_id(), 150 + detected_later);  // ids are never reused
}

TEST(PointTracker, UnrelatedFrameEndsTheTracks) {
  PointTrackerOptions options;
  options.target_count = 100;
  PointTracker tracker(options);
  tracker.Track(Texture(320, 240, 1));
  const PointTrackerFrame f = tracker.Track(Texture(320, 240, 2));
  EXPECT_EQ(f.stats.previous, 100);
  // Flow into an unrelated image fails, or fails the round trip, or the epipolar check.
  EXPECT_LT(f.stats.tracked, 15);
  EXPECT_EQ(f.stats.previous, f.stats.flow_failed + f.stats.forward_backward_failed +
                                  f.stats.ransac_outliers + f.stats.tracked);
  // A blank frame: no corners, no crash.
  const PointTrackerFrame blank = tracker.Track(cv::Mat(240, 320, CV_8UC1, cv::Scalar(90)));
  EXPECT_EQ(blank.stats.detected, 0);
}

TEST(PointTracker, BadInput) {
  PointTrackerOptions bad;
  bad.target_count = 0;
  EXPECT_THROW(PointTracker{bad}, std::invalid_argument);
  bad = PointTrackerOptions();
  bad.max_forward_backward_px = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(PointTracker{bad}, std::invalid_argument);
  EXPECT_THROW(PointTracker(PointTrackerOptions(), PinholeIntrinsics{0, 1, 0, 0}),
               std::invalid_argument);
  PointTracker tracker;
  EXPECT_THROW(tracker.Track(cv::Mat()), std::invalid_argument);
  EXPECT_THROW(tracker.Track(cv::Mat(10, 10, CV_8UC3)), std::invalid_argument);
  tracker.Track(Texture(64, 48, 3));
  EXPECT_THROW(tracker.Track(Texture(65, 48, 3)), std::invalid_argument);
  // Smaller than the border: nothing detected, nothing tracked, no crash.
  PointTracker tiny;
  EXPECT_EQ(tiny.Track(cv::Mat(10, 10, CV_8UC1, cv::Scalar(1))).stats.live(), 0);
}

// The real KITTI clip: 51 frames. A track of 3 or more views is correct when the point
// triangulated from the ground-truth cameras reprojects within 2 px in every view of the track.
TEST(PointTracker, RealKittiClip) {
  const fs::path data = fs::path(PLUCKER_SHARED_DATA_DIR) / "kitti-mono-clip";
  if (!fs::exists(data / "poses.txt")) GTEST_SKIP() << "shared data absent: " << data;
  const io::ImageFolder folder = io::OpenImageFolder((data / "image_0").string());
  const io::KittiCalibration calib = io::ReadKittiCalibration(
      (data / "calib.txt").string(), folder.size.width, folder.size.height);
  const io::Trajectory gt = io::ReadTrajectory((data / "poses.txt").string());
  ASSERT_EQ(gt.poses.size(), folder.files.size());

  PointTracker tracker(PointTrackerOptions(), calib.camera.K);
  std::map<int, std::vector<sensor::PointObservation>> tracks;
  long verified = 0, outliers = 0, fb_failed = 0, live = 0;
  for (const std::string& file : folder.files) {
    const PointTrackerFrame f = tracker.Track(io::ReadGrayImage(file));
    for (const auto& o : f.observations) tracks[o.point_id].push_back(o);
    verified += f.stats.tracked + f.stats.ransac_outliers;
    outliers += f.stats.ransac_outliers;
    fb_failed += f.stats.forward_backward_failed;
    live += f.stats.live();
  }
  int long_tracks = 0, correct = 0, views = 0;
  int bucket_tracks[4] = {0, 0, 0, 0}, bucket_correct[4] = {0, 0, 0, 0};  // 3, 4-5, 6-10, 11+
  for (const auto& [id, obs] : tracks) {
    if (obs.size() < 3) continue;
    std::vector<SE3d> T_w_c;
    std::vector<Eigen::Vector2d> uv;
    for (const auto& o : obs) {
      T_w_c.push_back(gt.poses[o.frame]);
      uv.push_back(o.uv);
    }
    ++long_tracks;
    views += static_cast<int>(obs.size());
    PointTriangulationOptions triangulation;
    triangulation.min_parallax_deg = 0.0;  // far points are fine: the test is reprojection
    const PointTriangulationResult r = TriangulatePoint(calib.camera.K, T_w_c, uv, triangulation);
    const int bucket = obs.size() <= 3 ? 0 : obs.size() <= 5 ? 1 : obs.size() <= 10 ? 2 : 3;
    ++bucket_tracks[bucket];
    if (!r.ok()) continue;
    bool all_within = true;
    for (std::size_t i = 0; i < obs.size(); ++i) {
      const Eigen::Vector3d p_c = T_w_c[i].Inverse() * r.p_w;
      const auto px = calib.camera.Project(p_c);
      all_within = all_within && px && (*px - uv[i]).norm() <= 2.0;
    }
    correct += all_within;
    bucket_correct[bucket] += all_within;
  }
  const double precision = static_cast<double>(correct) / long_tracks;
  const double inlier_share = 1.0 - static_cast<double>(outliers) / verified;
  std::printf(
      "KITTI clip, %zu frames: %zu tracks, %d of 3+ views (mean %.1f views), %.1f live per "
      "frame, RANSAC inlier share %.3f, forward-backward rejections %ld, correct 3+ view tracks "
      "(GT triangulation within 2 px) %.4f\n",
      folder.files.size(), tracks.size(), long_tracks, static_cast<double>(views) / long_tracks,
      static_cast<double>(live) / folder.files.size(), inlier_share, fb_failed, precision);
  std::printf("correct by length, 3 / 4-5 / 6-10 / 11+ views: %d/%d %d/%d %d/%d %d/%d\n",
              bucket_correct[0], bucket_tracks[0], bucket_correct[1], bucket_tracks[1],
              bucket_correct[2], bucket_tracks[2], bucket_correct[3], bucket_tracks[3]);
  EXPECT_GT(long_tracks, 1500);
  EXPECT_GT(inlier_share, 0.95);
  // Short tracks are right; long ones drift (frame-to-frame KLT re-templates every frame, and
  // in forward motion the drift runs along the epipolar lines, which no two-view check sees).
  EXPECT_GE(static_cast<double>(bucket_correct[0]) / bucket_tracks[0], 0.95);
  EXPECT_GE(precision, 0.8);
}

}  // namespace
}  // namespace vision
}  // namespace plucker
