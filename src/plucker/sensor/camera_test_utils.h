// Cameras shared by the tests (header-only, test use only, not installed).
#pragma once

#include "plucker/sensor/camera.h"

namespace plucker {
namespace sensor {
namespace testing {

// The EuRoC V1_01 cam0 calibration (sensor.yaml): strong barrel distortion, k1 = -0.28.
inline Camera EurocCam0() {
  Camera c;
  c.K = PinholeIntrinsics{458.654, 457.296, 367.215, 248.375};
  c.distortion.k1 = -0.28340811;
  c.distortion.k2 = 0.07395907;
  c.distortion.p1 = 0.00019359;
  c.distortion.p2 = 1.76187114e-05;
  c.width = 752;
  c.height = 480;
  return c;
}

}  // namespace testing
}  // namespace sensor
}  // namespace plucker
