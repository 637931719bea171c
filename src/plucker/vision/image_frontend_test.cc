#include "plucker/vision/image_frontend.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <set>
#include <stdexcept>

#include "plucker/io/camera_calibration.h"
#include "plucker/io/image_folder.h"

namespace plucker {
namespace vision {
namespace {

namespace fs = std::filesystem;

// The first frames of the real KITTI clip: points and segments come out with track ids that
// continue from frame to frame, and every stage is announced in order.
TEST(ImageFrontend, TracksPointsAndLinesOnTheKittiClip) {
  const fs::path data = fs::path(PLUCKER_SHARED_DATA_DIR) / "kitti-mono-clip";
  if (!fs::exists(data / "calib.txt")) GTEST_SKIP() << "shared data absent: " << data;
  const io::ImageFolder folder = io::OpenImageFolder((data / "image_0").string());
  const io::KittiCalibration calib = io::ReadKittiCalibration(
      (data / "calib.txt").string(), folder.size.width, folder.size.height);
  ImageFrontend frontend(calib.camera.K);
  constexpr int kFrames = 6;
  std::set<int> seen_lines, seen_points;
  int continued_lines = 0, continued_points = 0;
  for (int i = 0; i < kFrames; ++i) {
    std::vector<FrontendStage> stages;
    const ImageFrontendFrame f = frontend.Process(io::ReadGrayImage(folder.files[i]),
                                                  [&](FrontendStage s) { stages.push_back(s); });
    ASSERT_EQ(stages.size(), 4u);
    EXPECT_EQ(stages.front(), FrontendStage::kPoints);
    EXPECT_EQ(stages.back(), FrontendStage::kDone);
    EXPECT_GT(f.points.size(), 150u) << "frame " << i;
    EXPECT_GT(f.segments.size(), 40u) << "frame " << i;
    for (const auto& s : f.segments) {
      // Detected at min_segment_px or longer, then clipped to the margin the descriptor needs
      // and kept when still min_length_px long (line_matcher.h).
      EXPECT_GE((s.e_px - s.s_px).norm(), ImageFrontendOptions().lines.describe.min_length_px);
      continued_lines += seen_lines.count(s.line_id) > 0;
    }
    for (const auto& p : f.points) continued_points += seen_points.count(p.point_id) > 0;
    for (const auto& s : f.segments) seen_lines.insert(s.line_id);
    for (const auto& p : f.points) seen_points.insert(p.point_id);
  }
  // Most of what a frame sees was seen before (5 of the 6 frames can continue tracks).
  EXPECT_GT(continued_points, 5 * 150);
  EXPECT_GT(continued_lines, 5 * 20);
}

// The speed settings of `plucker vo` on images: at most max_segments segments (the longest),
// detected at half resolution and mapped back to full-resolution pixels (they still lie on the
// full-resolution edges: the tracker continues them from frame to frame). Measured on these 4
// frames, segments continuing a track: all segments at full resolution 379 of 1788 (21 %), the 60
// longest 77 of 240 (32 %), all at half resolution 123 of 1121 (11 %), the 60 longest at half
// resolution 37 of 240 (15 %): half-resolution endpoints are less repeatable, the price of the
// speed (docs/vo.md).
TEST(ImageFrontend, SegmentCapAndHalfResolutionDetectionOnTheKittiClip) {
  const fs::path data = fs::path(PLUCKER_SHARED_DATA_DIR) / "kitti-mono-clip";
  if (!fs::exists(data / "calib.txt")) GTEST_SKIP() << "shared data absent: " << data;
  const io::ImageFolder folder = io::OpenImageFolder((data / "image_0").string());
  const io::KittiCalibration calib = io::ReadKittiCalibration(
      (data / "calib.txt").string(), folder.size.width, folder.size.height);
  ImageFrontendOptions options;
  options.max_segments = 60;
  options.detection_scale = 0.5;
  ImageFrontend frontend(calib.camera.K, options);
  std::set<int> seen;
  int continued = 0, segments = 0;
  for (int i = 0; i < 4; ++i) {
    const ImageFrontendFrame f = frontend.Process(io::ReadGrayImage(folder.files[i]));
    EXPECT_LE(f.segments.size(), 60u);
    EXPECT_GT(f.segments.size(), 30u);
    for (const auto& s : f.segments) {
      EXPECT_GE((s.e_px - s.s_px).norm(), options.lines.describe.min_length_px);
      continued += seen.count(s.line_id) > 0;
    }
    segments += static_cast<int>(f.segments.size());
    for (const auto& s : f.segments) seen.insert(s.line_id);
  }
  std::printf("60 longest segments at half resolution: %d segments in 4 frames, %d continued\n",
              segments, continued);
  EXPECT_GT(continued, 25);
  ImageFrontendOptions bad;
  bad.detection_scale = 0.0;
  EXPECT_THROW(ImageFrontend(calib.camera.K, bad), std::invalid_argument);
  bad.detection_scale = 1.0;
  bad.max_segments = -1;
  EXPECT_THROW(ImageFrontend(calib.camera.K, bad), std::invalid_argument);
}

TEST(ImageFrontend, PointsOnlyAndBadInput) {
  ImageFrontendOptions options;
  options.use_lines = false;
  ImageFrontend frontend(PinholeIntrinsics{300, 300, 160, 120}, options);
  cv::Mat image(240, 320, CV_8UC1);
  cv::randu(image, 0, 255);
  const ImageFrontendFrame f = frontend.Process(image);
  EXPECT_GT(f.points.size(), 0u);
  EXPECT_TRUE(f.segments.empty());
  EXPECT_THROW(frontend.Process(cv::Mat(100, 100, CV_8UC1, cv::Scalar(0))), std::invalid_argument);
  EXPECT_THROW(frontend.Process(cv::Mat()), std::invalid_argument);
}

}  // namespace
}  // namespace vision
}  // namespace plucker
