// A camera mounted on the body (the IMU / vehicle frame b): intrinsics, image size, and the
// extrinsic T_b_c (camera frame c expressed in b, so p_b = T_b_c p_c).
//
// Pixel coordinates: u right, v down, pixel centres at integers, the image is
// [0, width - 1] x [0, height - 1]. Camera frame: z forward (optical axis), x right, y down.
// Today the model is the ideal pinhole (geometry/camera.h); the camera models with lens
// distortion (radial-tangential, as EuRoC needs) belong in this layer next to it.
#pragma once

#include "plucker/geometry/camera.h"
#include "plucker/geometry/se3.h"

namespace plucker {
namespace sensor {

struct CameraRig {
  PinholeIntrinsics K{400.0, 400.0, 319.5, 239.5};
  int width = 640;
  int height = 480;
  SE3d T_b_c;  // identity unless set (the simulator's default rig: sim::DefaultRig())
};

}  // namespace sensor
}  // namespace plucker
