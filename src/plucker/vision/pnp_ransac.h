// Two-view and absolute pose by RANSAC over OpenCV, written once for the sliding window (tracking
// fallback, two-view start) and the reconstruction (registration, pair verification):
// - PnpRansac: the pose T_c_w of a calibrated camera from 3D-2D correspondences.
// - EssentialPose: the relative pose (R_b_a, unit t_b_a) of two calibrated views from matches in
//   normalised coordinates (five-point essential matrix, then the cheirality check).
// Each takes its settings in an options struct (the callers pass theirs: the window's and the
// reconstruction's differ in solver, iterations and thresholds) and returns a status: no OpenCV
// exception escapes (a cv::Exception is caught and reported as kError with its message).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/se3.h"

namespace plucker {
namespace vision {

enum class PnpSolver { kEpnp, kAp3p, kP3p, kIterative, kSqpnp };

struct PnpRansacOptions {
  PnpSolver solver = PnpSolver::kEpnp;  // the minimal solver inside RANSAC
  int iterations = 200;                 // RANSAC iterations at most
  double threshold_px = 3.0;            // reprojection inlier threshold [px]
  double confidence = 0.999;            // RANSAC stopping confidence
  int min_correspondences = 6;          // fewer: not tried (kTooFewCorrespondences)
  int min_inliers = 6;                  // fewer inliers: kTooFewInliers
};

enum class PnpStatus {
  kOk,
  kTooFewCorrespondences,
  kNoSolution,     // RANSAC found no model
  kTooFewInliers,  // a model, below min_inliers
  kNotFinite,      // the solver returned a non-finite pose
  kError,          // OpenCV threw (message holds its text)
};

struct PnpRansacResult {
  PnpStatus status = PnpStatus::kNoSolution;
  SE3d T_c_w;                // world to camera; meaningful when status == kOk
  std::vector<int> inliers;  // indices into the correspondences (also on kTooFewInliers)
  std::string message;       // empty on kOk
  bool ok() const { return status == PnpStatus::kOk; }
};

// points_w[i] (world) is seen at pixel uv[i] of the ideal pinhole camera K (no distortion).
PnpRansacResult PnpRansac(const std::vector<Eigen::Vector3d>& points_w,
                          const std::vector<Eigen::Vector2d>& uv, const PinholeIntrinsics& K,
                          const PnpRansacOptions& options);

struct EssentialPoseOptions {
  // RANSAC epipolar threshold in normalised-plane units (a pixel threshold divided by the focal
  // length in pixels).
  double threshold = 1e-3;
  double confidence = 0.999;
  // The cheirality test counts a match as an inlier when its triangulated depth is in (0, this)
  // in units of the (unit) baseline; 50 is OpenCV's default. A short baseline in a deep scene
  // (a drone taking off in a hall: 1 cm against 5 m) puts the right solution's points beyond 50
  // and a wrong one with near points wins.
  double max_depth_baselines = 50.0;
  // With exactly five matches OpenCV returns every five-point solution stacked (3k x 3): true
  // takes the first (the reconstruction), false fails with kNoEssentialMatrix (the window).
  bool take_first_of_several = false;
};

enum class EssentialPoseStatus { kOk, kTooFewMatches, kNoEssentialMatrix, kError };

struct EssentialPoseResult {
  EssentialPoseStatus status = EssentialPoseStatus::kNoEssentialMatrix;
  Eigen::Matrix3d R_b_a = Eigen::Matrix3d::Identity();  // x_b = R_b_a x_a + t_b_a
  Eigen::Vector3d t_b_a = Eigen::Vector3d::Zero();      // unit length (as OpenCV returns it)
  int inliers = 0;  // RANSAC inliers in front of both cameras (cv::recoverPose's count)
  std::vector<unsigned char> inlier_mask;  // per match: 1 for those inliers
  std::string message;                     // empty on kOk
  bool ok() const { return status == EssentialPoseStatus::kOk; }
};

// xa[i] in view a matches xb[i] in view b, both on the normalised plane (z = 1). At least five.
EssentialPoseResult EssentialPose(const std::vector<Eigen::Vector2d>& xa,
                                  const std::vector<Eigen::Vector2d>& xb,
                                  const EssentialPoseOptions& options);

}  // namespace vision
}  // namespace plucker
