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

// The TUM-VI cam0 calibration (Kalibr pinhole-equi, 512x512, a 195 deg lens): the image corners
// lie beyond 90 deg from the axis, outside the camera's valid field of view.
inline Camera TumViCam0() {
  Camera c;
  c.K = PinholeIntrinsics{190.97847715128717, 190.9733070521226, 254.93170605935475,
                          256.8974428996504};
  c.model = CameraModel::kEquidistant;
  c.equidistant = EquidistantDistortion{0.0034823894022493434, 0.0007150348452162257,
                                        -0.0020532361418706202, 0.00020293673591811182};
  c.width = 512;
  c.height = 512;
  return c;
}

}  // namespace testing
}  // namespace sensor
}  // namespace plucker
