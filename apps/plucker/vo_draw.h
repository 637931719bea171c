// `plucker vo --draw DIR` and `plucker vio --draw DIR`: one PNG per frame with the frame's
// observations and the window's landmarks drawn on the image (app-side OpenCV drawing; the window
// layer does no I/O).
//   green dot:     point track with a landmark in the window (inlier of the frame's pose),
//   yellow dot:    point track without a landmark (not triangulated yet, or culled);
//   blue segment:  detected and tracked segment;
//   red segment:   the window's 3D line of that track reprojected with the frame's pose (the
//                  observed endpoints projected onto the reprojected image line).
#pragma once

#include <map>
#include <string>

#include <opencv2/core.hpp>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/plucker_line.h"
#include "plucker/geometry/se3.h"
#include "plucker/vision/undistort.h"
#include "plucker/window/sliding_window_estimator.h"

namespace plucker {
namespace app {

// The overlay of one frame on `gray` (8-bit, the observations' image); returns a BGR image.
cv::Mat DrawVoFrame(const cv::Mat& gray, const PinholeIntrinsics& K,
                    const window::FrameInput& frame, const SE3d& T_w_c,
                    const std::map<int, Eigen::Vector3d>& points_w,
                    const std::map<int, Line6d>& lines_w);

// Writes DIR/%06d.png (frame i) of the raw 8-bit image `gray` undistorted (when `undistorter`),
// with the map's landmarks; throws io::IoError when the PNG cannot be written.
void WriteFrameOverlay(const std::string& dir, const cv::Mat& gray,
                       const vision::Undistorter* undistorter, const PinholeIntrinsics& K,
                       const window::FrameInput& frame, int i, const SE3d& T_w_c,
                       const window::SlidingWindowEstimator& map);

// Writes DIR/%06d.png (frame i) of the image file undistorted (when `undistorter`), with the
// map's landmarks. An unreadable image is skipped (already warned about); throws io::IoError when
// the PNG cannot be written.
void WriteVoOverlay(const std::string& dir, const std::string& image,
                    const vision::Undistorter* undistorter, const PinholeIntrinsics& K,
                    const window::FrameInput& frame, int i, const SE3d& T_w_c,
                    const window::SlidingWindowEstimator& map);

}  // namespace app
}  // namespace plucker
