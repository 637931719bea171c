// Two-view initialisation of monocular odometry from point tracks: the essential matrix of the
// common tracks (OpenCV's five-point solver in RANSAC on normalised coordinates), its
// decomposition by the cheirality test, and a parallax test so that a pure rotation or a too-short
// baseline is refused. The translation has unit norm: monocular scale is unobservable, the
// estimator keeps this arbitrary scale.
#pragma once

#include <string>
#include <vector>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/se3.h"
#include "plucker/sensor/camera_observations.h"

namespace plucker {
namespace window {

struct TwoViewOptions {
  int min_common_tracks = 12;        // tracks seen in both frames
  int min_inliers = 10;              // essential-matrix inliers in front of both cameras
  double min_parallax_px = 15.0;     // rotation-compensated median parallax of the inliers
  double ransac_threshold_px = 1.5;  // epipolar distance, pixels
  double min_inlier_ratio = 0.5;
};

struct TwoViewResult {
  bool ok = false;
  std::string message;  // why not, when !ok
  SE3d T_b_a;           // camera a in camera b, |t| = 1
  int common_tracks = 0;
  int inliers = 0;
  double parallax_px = 0.0;
};

TwoViewResult InitializeTwoView(const PinholeIntrinsics& K,
                                const std::vector<sensor::PointObservation>& a,
                                const std::vector<sensor::PointObservation>& b,
                                const TwoViewOptions& options = {});

}  // namespace window
}  // namespace plucker
