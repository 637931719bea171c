// Incremental structure from motion with points and lines, for a set of calibrated images
// (undistorted, one pinhole K). The top level reads as the algorithm:
//   features      per image: SIFT keypoints (OpenCV, detected at a reduced size when the image is
//                 large, keypoints scaled back to full-size pixels) and line segments
//                 (vision/line_detector, edlines-refined) with LBD descriptors
//                 (vision/line_matcher);
//   matching      every pair of views: SIFT nearest neighbours (FLANN, ratio test, one match per
//                 keypoint), verified by an essential matrix in RANSAC; point tracks by union of
//                 the verified matches (a track seen twice in one view is dropped);
//   initialise    the verified pair with the most inliers whose median triangulation angle reaches
//                 min_init_angle_deg: relative pose from the essential matrix, |t| = 1;
//   register      the unregistered view that sees the most triangulated tracks, by PnP in RANSAC;
//                 its lines are matched with the registered views (LBD, epipolar gating with the
//                 PnP pose) and joined to line tracks; where the PnP inliers are scarce the pose is
//                 refined with the points and the triangulated lines together;
//   triangulate   new points (N-view, geometry/point_triangulation) and line tracks of 3 or more
//                 views (geometry/line_triangulation: linear, refined on the line manifold, with
//                 the conditioning test);
//   adjust        bundle adjustment (ba/bundle_adjustment: analytic point and line factors, the
//                 line manifold, Huber loss) after each registration, outlier rejection by
//                 reprojection error, and a final global adjustment.
// Gauge: the world is the first camera of the initial pair, the scale its baseline (1).
// No file I/O, no printing, no timing: stages are announced to an observer, the caller times them.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/line_triangulation.h"
#include "plucker/geometry/plucker_line.h"
#include "plucker/geometry/point_triangulation.h"
#include "plucker/geometry/se3.h"
#include "plucker/vision/line_detector.h"
#include "plucker/vision/line_matcher.h"

namespace plucker {
namespace sfm {

struct FeatureOptions {
  // SIFT runs on the image reduced so that its longer side is at most this (0: full size). The
  // cost of SIFT grows with the pixel count (8-25 s per 3072x2048 image here).
  int detection_max_side = 1536;
  int max_keypoints = 8000;  // SIFT's nfeatures (the strongest are kept)
  bool detect_lines = true;
  vision::LineDetectorOptions line_detector;  // on the full-size image
  double min_line_length_px = 40.0;           // shorter segments are not used
  int max_lines = 1500;                       // the longest are kept
};

// What one view offers to the reconstruction (ideal pixels of the full-size image).
struct ViewFeatures {
  int width = 0, height = 0;
  std::vector<Eigen::Vector2d> keypoints;
  cv::Mat descriptors;         // keypoints.size() x 128, CV_32F (any float descriptor works)
  vision::LineFeatures lines;  // segments with LBD descriptors
};

// SIFT keypoints and line segments of a grayscale image (CV_8UC1; std::invalid_argument when
// empty). An image without texture gives no features (not an error).
ViewFeatures ExtractFeatures(const cv::Mat& gray, const FeatureOptions& options = {});

enum class SfmStage {
  kMatching,
  kInitialization,
  kRegistration,
  kTriangulation,
  kLines,
  kAdjustment,
  kDone
};
constexpr int kNumSfmStages = 6;
const char* ToString(SfmStage stage);

struct SfmOptions {
  // Matching and verification.
  double match_ratio = 0.8;             // Lowe's ratio test
  double essential_threshold_px = 1.0;  // RANSAC epipolar threshold
  int min_pair_inliers = 30;            // a verified pair has at least this many inliers
  // Point budget: at most this many point tracks are used; 0 = all. The kept tracks are the
  // longest (point_subset_seed 0) or a uniform random subset drawn with point_subset_seed (> 0),
  // the same subset for the same seed whatever the other options (e.g. with or without lines).
  int max_points = 0;
  int point_subset_seed = 0;
  // Initialisation and registration.
  double min_init_angle_deg = 3.0;  // median triangulation angle of the initial pair
  int min_pnp_inliers = 15;
  double pnp_threshold_px = 3.0;
  int scarce_points = 100;  // below this many PnP inliers the pose is refined with lines too
  // Triangulation and outlier rejection.
  double min_triangulation_angle_deg = 1.0;
  double max_reprojection_px = 2.0;  // point observations / line endpoints further are rejected
  // Lines.
  bool use_lines = true;
  int min_line_views = 3;
  vision::LineMatcherOptions line_matcher = DefaultLineMatcher();
  LineTriangulationOptions line_triangulation;
  // Bundle adjustment.
  double huber_px = 1.0;  // Huber scale, in units of each residual's sigma
  // Measurement standard deviations: the endpoint-to-line distances of detected segments are
  // noisier than SIFT keypoints. On fountain-P11 after the final adjustment the mean endpoint
  // distance is 0.325 px (sigma = mean / sqrt(2 / pi) = 0.41 px) and the mean point error norm
  // 0.27 px (sigma per axis = mean / sqrt(pi / 2) = 0.215 px): a ratio of 1.9, hence 2.
  double point_sigma_px = 1.0;
  double line_sigma_px = 2.0;
  int local_iterations = 10;  // after each registration
  int final_iterations = 50;  // the final global adjustment
  // Threads for the pairwise matching and the line matching (the results do not depend on it).
  // The adjustments run on one thread: Ceres' multi-threaded Schur elimination sums in a varying
  // order, and runs that repeat exactly are what makes two configurations comparable.
  int num_threads = 1;

  static vision::LineMatcherOptions DefaultLineMatcher();
};

// A triangulated 3D point with its observations (view, keypoint index).
struct SfmPoint {
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
  std::vector<std::pair<int, int>> observations;
};

// A triangulated 3D line (Plücker, |d| = 1), its segment and observations (view, segment index
// into ViewFeatures::lines.segments).
struct SfmLine {
  Line6d L_w = Line6d::Zero();
  Eigen::Vector3d start_w = Eigen::Vector3d::Zero(), end_w = Eigen::Vector3d::Zero();
  std::vector<std::pair<int, int>> observations;
};

struct SfmStatistics {
  int views = 0;
  int registered = 0;
  int verified_pairs = 0;
  int point_tracks = 0;  // tracks of 2+ views before the budget
  int points = 0;        // triangulated, in the result
  int lines = 0;
  int point_observations = 0;
  int line_observations = 0;
  double mean_point_error_px = 0.0;  // reprojection error norm over the point observations
  double mean_line_error_px = 0.0;   // endpoint-to-line distance over the line endpoints
  int init_a = -1, init_b = -1;
  int rejected_point_observations = 0;
  int rejected_line_observations = 0;
  int adjustments = 0;
  int line_refined_registrations = 0;  // poses refined with lines (scarce points)
};

struct SfmResult {
  bool ok = false;
  std::string message;                     // why not, when !ok
  std::vector<std::optional<SE3d>> T_w_c;  // per view; nullopt: not registered
  std::vector<std::string> view_status;    // "registered" or why not
  std::vector<SfmPoint> points;
  std::vector<SfmLine> lines;
  SfmStatistics stats;
};

using SfmObserver = std::function<void(SfmStage)>;
// Progress of long stages (e.g. "registered view 4: 812 PnP inliers"), for the caller to show.
using SfmProgress = std::function<void(const std::string&)>;

// K: intrinsics of the (undistorted) full-size images; views: one per image, in order (an empty
// ViewFeatures is a view that could not be read: it stays unregistered). Never throws for bad
// data: !ok with a message when no initial pair is found.
SfmResult Reconstruct(const PinholeIntrinsics& K, const std::vector<ViewFeatures>& views,
                      const SfmOptions& options = {}, const SfmObserver& observer = {},
                      const SfmProgress& progress = {});

}  // namespace sfm
}  // namespace plucker
