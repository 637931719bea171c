// The image pyramid of pyramidal Lucas-Kanade flow, built once per image and shared by every
// tracker that follows points from or into that image (point_tracker.h, line_tracker.h).
//
// cv::calcOpticalFlowPyrLK given two images builds both pyramids and the Scharr derivatives of
// the first on every call: the point tracker's forward and backward flow and the line tracker's
// flow prediction built six pyramids and three derivative pyramids per frame for two images.
// A FlowPyramid holds the levels with their derivatives (cv::buildOpticalFlowPyramid), padded
// for windows up to window_px, so that each image's pyramid is built once and flow in either
// direction reuses it. Flow on shared pyramids equals flow on the images up to the border
// treatment of the derivatives (tested).
// No I/O, no timing.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace plucker {
namespace vision {

class FlowPyramid {
 public:
  FlowPyramid() = default;
  // image: CV_8UC1, non-empty (std::invalid_argument otherwise, also for window_px < 3 or
  // max_level < 0). Flow windows up to window_px and levels up to max_level can use it.
  FlowPyramid(const cv::Mat& image, int window_px, int max_level);

  bool empty() const { return levels_.empty(); }
  const cv::Mat& image() const { return image_; }  // an own copy (a view of the padded level 0)
  cv::Size size() const { return image_.size(); }
  int window_px() const { return window_px_; }
  int max_level() const { return max_level_; }
  const std::vector<cv::Mat>& levels() const { return levels_; }

 private:
  cv::Mat image_;
  std::vector<cv::Mat> levels_;  // image, derivatives, image, derivatives, ... (with padding)
  int window_px_ = 0;
  int max_level_ = 0;
};

// Pyramidal Lucas-Kanade flow of `points` from image `from` into image `to` (both of the same
// size), with a square window of window_px (<= both pyramids' window_px) on up to max_level
// levels (clipped to the pyramids'), at most max_iterations Gauss-Newton steps per level (OpenCV's
// default 30; steps stop below 0.01 px). status[i] != 0 where flow converged. Throws
// std::invalid_argument for empty or mismatched pyramids or a too large window.
void PyramidFlow(const FlowPyramid& from, const FlowPyramid& to,
                 const std::vector<cv::Point2f>& points, int window_px, int max_level,
                 std::vector<cv::Point2f>* moved, std::vector<unsigned char>* status,
                 int max_iterations = 30);

}  // namespace vision
}  // namespace plucker
