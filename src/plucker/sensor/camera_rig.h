// A camera mounted on the body (the IMU / vehicle frame b): intrinsics, image size, and the
// extrinsic T_b_c (camera frame c expressed in b, so p_b = T_b_c p_c).
//
// Pixel coordinates: u right, v down, pixel centres at integers, the image is
// [0, width - 1] x [0, height - 1]. Camera frame: z forward (optical axis), x right, y down.
// The ideal pinhole (geometry/camera.h) by default. A fisheye rig (the simulator's
// `--camera-model kb`, docs/sim-format.md): K, width and height are the raw Kannala-Brandt camera
// (sensor/camera.h), and `fisheye` holds its coefficients and the undistorted pinhole view in
// which the segments (and the points when points_in_view) are given; the points are otherwise
// raw (distorted) pixels of the full fisheye image.
#pragma once

#include <optional>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/equidistant.h"
#include "plucker/geometry/se3.h"

namespace plucker {
namespace sensor {

struct FisheyeView {
  EquidistantDistortion coeffs;  // Kalibr's equidistant k1..k4
  PinholeIntrinsics view_K;      // the undistorted pinhole view of the segments
  int view_width = 0;
  int view_height = 0;
  bool points_in_view = false;  // points in the view (true) or raw pixels of the full image
};

struct CameraRig {
  PinholeIntrinsics K{400.0, 400.0, 319.5, 239.5};
  int width = 640;
  int height = 480;
  SE3d T_b_c;  // identity unless set (the simulator's default rig: sim::DefaultRig())
  std::optional<FisheyeView> fisheye;  // none: the pinhole K above
};

}  // namespace sensor
}  // namespace plucker
