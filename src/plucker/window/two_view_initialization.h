// Two-view initialisation of monocular odometry from point tracks: the essential matrix of the
// common tracks (OpenCV's five-point solver in RANSAC on normalised coordinates), its
// decomposition by the cheirality test, and a parallax test so that a pure rotation or a too-short
// baseline is refused. The translation has unit norm: monocular scale is unobservable, the
// estimator keeps this arbitrary scale.
//
// With a known relative rotation (visual-inertial: the gyroscope integrated between the two
// frames), the essential matrix's rotation must agree with it. Under forward motion with a short
// baseline the five-point solution can trade a translation for a rotation (the bas-relief
// ambiguity: a sideways translation plus a turn explains the same flow); its wrong rotation then
// also inflates the rotation-compensated parallax it is tested with (the simulated corridor: 4.2
// deg off, 29 px "parallax" for 5 px true).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/se3.h"
#include "plucker/sensor/camera_observations.h"

namespace plucker {
namespace window {

struct TwoViewOptions {
  int min_common_tracks = 12;     // tracks seen in both frames
  int min_inliers = 10;           // essential-matrix inliers in front of both cameras
  double min_parallax_px = 15.0;  // rotation-compensated median parallax of the inliers
  // The translation must show: the median parallax of the inliers left after the best pure
  // rotation (fitted to them, not the essential matrix's rotation: with no translation that one
  // is arbitrary and its "parallax" is noise taken as motion) at least this (0: not tested).
  double min_translation_parallax_px = 0.0;
  // Median angle between the two rays of the inliers triangulated with the essential matrix's
  // pose, at least this (0: not tested).
  double min_triangulation_angle_deg = 0.0;
  double ransac_threshold_px = 1.5;  // epipolar distance, pixels
  double min_inlier_ratio = 0.5;
  // Inliers must triangulate in front of both cameras, nearer than this many baselines (OpenCV's
  // 50 refused the right solution of a short pair in a deep scene: docs/vo.md, MH_05).
  double max_depth_baselines = 50.0;
  // With a known rotation: the largest angle between it and the essential matrix's rotation
  // (the caller includes what the known rotation's own error can be, e.g. an unknown gyro bias).
  double max_rotation_disagreement_deg = 2.0;
};

struct TwoViewResult {
  bool ok = false;
  std::string message;  // why not, when !ok
  SE3d T_b_a;           // camera a in camera b, |t| = 1
  int common_tracks = 0;
  int inliers = 0;
  double parallax_px = 0.0;                // after the essential matrix's rotation
  double translation_parallax_px = 0.0;    // after the best pure rotation
  double triangulation_angle_deg = 0.0;    // median over the inliers
  double rotation_disagreement_deg = 0.0;  // against the known rotation (0 without one)
};

// R_b_a_known: the rotation of camera a in camera b from another sensor, or none.
TwoViewResult InitializeTwoView(const PinholeIntrinsics& K,
                                const std::vector<sensor::PointObservation>& a,
                                const std::vector<sensor::PointObservation>& b,
                                const TwoViewOptions& options = {},
                                const std::optional<Eigen::Matrix3d>& R_b_a_known = std::nullopt);

}  // namespace window
}  // namespace plucker
