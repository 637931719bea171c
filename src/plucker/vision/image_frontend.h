// The visual front end of the odometry on real images: for every (undistorted, 8-bit grayscale)
// image of a sequence,
//   1. points:   KLT point tracks with epipolar RANSAC (point_tracker.h);
//   2. segments: line segments (line_detector.h), those shorter than min_segment_px dropped;
//   3. lines:    segment tracks (line_tracker.h), gated by the epipolar geometry the point
//                tracker's RANSAC estimated between this frame and the previous one.
// Each image's flow pyramid (flow_pyramid.h) is built once and used by both trackers.
// Output: the frame's observations with track ids (sensor/camera_observations.h), the form the
// estimators take from the simulator or a features folder alike. No I/O, no timing: the stages
// are announced to an observer so that the caller can time them.
#pragma once

#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "plucker/geometry/camera.h"
#include "plucker/sensor/camera_observations.h"
#include "plucker/vision/line_detector.h"
#include "plucker/vision/line_tracker.h"
#include "plucker/vision/point_tracker.h"

namespace plucker {
namespace vision {

struct ImageFrontendOptions {
  PointTrackerOptions points;
  LineDetectorOptions detector;
  LineTrackerOptions lines;
  bool use_lines = true;
  double min_segment_px = 30.0;  // shorter segments are not tracked (poorly conditioned)
  // At most this many segments per image, the longest (0: all). Description, flow prediction
  // and matching cost grow with the count (about 480 segments of >= 30 px per KITTI image).
  int max_segments = 0;
  // Segments are detected on the image resized by this factor (0 < s <= 1; INTER_AREA) and
  // mapped back to full-resolution pixels; description and tracking stay at full resolution.
  // 0.5 quarters the detection time (EDLines scans every pixel).
  double detection_scale = 1.0;
};

struct ImageFrontendFrame {
  std::vector<sensor::PointObservation> points;      // point_id = track id
  std::vector<sensor::SegmentObservation> segments;  // line_id = track id
  PointTrackerStats point_stats;
  LineDetectionStats detection_stats;
  LineTrackerStats line_stats;
};

enum class FrontendStage { kPoints, kDetection, kLines, kDone };
constexpr int kNumFrontendStages = 3;
using FrontendObserver = std::function<void(FrontendStage)>;

class ImageFrontend {
 public:
  // K: the pinhole of the undistorted images. Throws std::invalid_argument for invalid options.
  ImageFrontend(const PinholeIntrinsics& K, const ImageFrontendOptions& options = {});

  // The next image (CV_8UC1, the size of the first; std::invalid_argument otherwise).
  ImageFrontendFrame Process(const cv::Mat& gray, const FrontendObserver& observer = {});

 private:
  PinholeIntrinsics K_;
  ImageFrontendOptions options_;
  PointTracker point_tracker_;
  LineTracker line_tracker_;
};

}  // namespace vision
}  // namespace plucker
