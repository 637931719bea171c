// Undistortion of whole images: a raw (distorted) image of a sensor::Camera is warped once into
// the image of an ideal pinhole, the model the factors use, so that straight 3D lines are
// straight in it and line segments can be detected there (sensor/camera.h says why).
//
// The maps are built once per camera (cv::initUndistortRectifyMap, fixed-point CV_16SC2 maps,
// 1/32 px resolution, for cv::remap's fast path) and reused for every frame. OpenCV's "plumb
// bob" model (k1, k2, p1, p2, k3) is the radial-tangential model of geometry/distortion.h, term
// for term; an equidistant (Kannala-Brandt, fisheye) camera is mapped with
// cv::fisheye::initUndistortRectifyMap, whose [k1, k2, k3, k4] are geometry/equidistant.h's.
//
// Fisheye: the output is a pinhole view of the lens's central field of view (a pinhole cannot
// show 180 deg). With the default (the camera's own K and size) the view keeps the lens's
// resolution at the centre and spans 2 atan(w / 2 fx) horizontally (TUM-VI's 512 px at fx = 191:
// 107 deg; T265's 848 px at fx = 285: 112 deg), so the whole view stays inside the lens's valid
// angle. A wider view: a smaller output focal length (output_K, e.g. fx = w / (2 tan(fov / 2))
// for a horizontal field of view fov), at the price of the centre's resolution and of
// stretched, blurred borders (a pinhole magnifies the periphery by 1 / cos^2 of the angle);
// the factors must then use that K (ideal_camera()).
//
// Output pinhole (UndistorterOptions):
//   default       the camera's own K and image size: ideal pixels are in the calibration's units,
//                 with the same principal point. Under barrel distortion (k1 < 0, EuRoC) the
//                 output shows a little less than the raw field of view (the raw image's outer
//                 margin is cut off, no black border); under pincushion distortion (k1 > 0) the
//                 output's corners are black where the raw image has no data.
//   output_K/size a chosen pinhole, e.g. a smaller focal length to keep the whole raw field of
//                 view, or a smaller size for speed. The factors must then use that K
//                 (Undistorter::ideal_camera()).
// Output pixels whose source lies outside the raw image are 0 (cv::BORDER_CONSTANT).
// Zero distortion with the same K and size is the identity: Undistort returns the input (the
// same cv::Mat header, no copy, no work).
#pragma once

#include <Eigen/Core>
#include <optional>

#include <opencv2/core.hpp>

#include "plucker/sensor/camera.h"

namespace plucker {
namespace vision {

struct UndistorterOptions {
  std::optional<PinholeIntrinsics> output_K;  // default: the camera's K
  int output_width = 0;                       // 0: the camera's width
  int output_height = 0;                      // 0: the camera's height
};

class Undistorter {
 public:
  // Throws std::invalid_argument for an invalid camera or output pinhole (the problem named).
  explicit Undistorter(const sensor::Camera& camera, const UndistorterOptions& options = {});

  // The raw camera and the ideal pinhole of the output images (zero distortion).
  const sensor::Camera& raw_camera() const { return raw_; }
  const sensor::Camera& ideal_camera() const { return ideal_; }
  bool IsIdentity() const { return identity_; }

  // The undistorted image of a raw image of the camera's size (any type cv::remap takes,
  // bilinear). Throws std::invalid_argument when the image is empty or of another size.
  cv::Mat Undistort(const cv::Mat& raw) const;

  // Point-wise versions of the same mapping: raw pixel -> output pixel and back; nullopt
  // outside the valid region of the distortion inverse.
  std::optional<Eigen::Vector2d> IdealFromRaw(const Eigen::Vector2d& uv_raw) const;
  std::optional<Eigen::Vector2d> RawFromIdeal(const Eigen::Vector2d& uv_ideal) const;

 private:
  sensor::Camera raw_;
  sensor::Camera ideal_;
  bool identity_ = false;
  cv::Mat map1_, map2_;  // CV_16SC2 / CV_16UC1 maps of cv::convertMaps
};

}  // namespace vision
}  // namespace plucker
