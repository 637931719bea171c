// Point tracks over an image sequence (KLT): for every new frame,
//   1. track: pyramidal Lucas-Kanade flow of every live track from the previous frame
//      (cv::calcOpticalFlowPyrLK on the frames' pyramids, flow_pyramid.h: each frame's pyramid
//      is built once, or passed in by the caller who shares it), and back again; a track survives
//      when both directions converge, the round trip returns within max_forward_backward_px and it
//      stays inside the image;
//   2. verify: RANSAC on the essential matrix (given the pinhole K; the images must be
//      undistorted, vision/undistort.h) or, without K, the fundamental matrix; epipolar
//      outliers end their track; the model is returned as F_cur_prev (for the line gate);
//   3. detect: new Shi-Tomasi corners (cv::goodFeaturesToTrack) away from the surviving tracks
//      (min_distance_px), up to target_count live tracks, each with a new track id; only in
//      frames whose surviving tracks fall below detect_below_share x target_count (the corner
//      response of the whole image is the tracker's largest cost).
// Track ids are never reused. Output: the frame's observations as sensor::PointObservation
// (point_id = track id), the form the simulator and the estimators use, with statistics.
// No I/O, no timing (the caller times it).
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "plucker/geometry/camera.h"
#include "plucker/sensor/camera_observations.h"
#include "plucker/vision/flow_pyramid.h"

namespace plucker {
namespace vision {

struct PointTrackerOptions {
  int target_count = 400;  // live tracks kept after re-detection
  // Corners are detected only when fewer than this share of target_count tracks survived
  // (in (0, 1]; 1: whenever one is missing).
  double detect_below_share = 1.0;
  double min_distance_px = 12.0;          // between corners (new ones and live tracks)
  double quality_level = 0.01;            // goodFeaturesToTrack: relative corner strength
  int block_size = 3;                     // goodFeaturesToTrack: corner window
  int border_px = 8;                      // no corners or tracks closer to the image border
  int window_px = 11;                     // KLT window (square)
  int pyramid_levels = 4;                 // KLT pyramid levels above the image
  double max_forward_backward_px = 0.25;  // forward-backward round-trip error accepted
  double ransac_threshold_px = 1.0;       // epipolar distance of a RANSAC inlier
  double ransac_confidence = 0.999;
  int min_ransac_points = 8;  // fewer tracked points: no RANSAC (stats.ransac_run false)
};

struct PointTrackerStats {
  int previous = 0;     // live tracks entering the frame
  int flow_failed = 0;  // KLT lost or left the image
  int forward_backward_failed = 0;
  int ransac_outliers = 0;
  bool ransac_run = false;
  int ransac_inliers = 0;
  int tracked = 0;             // survivors (continued tracks)
  int detected = 0;            // new tracks
  bool detection_run = false;  // corners were searched (see detect_below_share)
  int live() const { return tracked + detected; }
};

struct PointTrackerFrame {
  int frame = 0;                                       // 0-based index of Track() calls
  std::vector<sensor::PointObservation> observations;  // continued tracks first, then new ones
  PointTrackerStats stats;
  // The epipolar model of step 2 as x_cur^T F x_prev = 0 (F = K^-T E K^-1 with K; unit norm);
  // nullopt when RANSAC did not run or gave no unique model.
  std::optional<Eigen::Matrix3d> F_cur_prev;
};

class PointTracker {
 public:
  // K: the pinhole of the (undistorted) images, for RANSAC on the essential matrix; without
  // it the fundamental matrix is used. Throws std::invalid_argument for invalid options or K.
  explicit PointTracker(const PointTrackerOptions& options = {},
                        const std::optional<PinholeIntrinsics>& K = std::nullopt);

  // Tracks into the next frame (8-bit grayscale, the size of the first frame). Throws
  // std::invalid_argument for an empty image, another type or another size.
  PointTrackerFrame Track(const cv::Mat& image);
  // The same on the frame's pyramid (built by the caller, e.g. shared with the line tracker):
  // its window_px must be >= options.window_px (std::invalid_argument otherwise); the flow uses
  // min(pyramid_levels, pyramid.max_level()) levels.
  PointTrackerFrame Track(const FlowPyramid& pyramid);

  int next_track_id() const { return next_id_; }

 private:
  void FlowAndCheck(const FlowPyramid& pyramid, PointTrackerFrame* out);
  void RejectEpipolarOutliers(std::vector<cv::Point2f>* prev_points, PointTrackerFrame* out);
  void Detect(const cv::Mat& image, PointTrackerFrame* out);

  PointTrackerOptions options_;
  std::optional<PinholeIntrinsics> K_;
  FlowPyramid previous_;
  std::vector<cv::Point2f> points_;  // live tracks in the previous frame
  std::vector<int> ids_;             // their track ids
  int next_id_ = 0;
  int frame_ = 0;
};

// The fundamental matrix x_b^T F x_a = 0 of an OpenCV RANSAC model (3x3 CV_64F): with K the
// model is the essential matrix and F = K^-T E K^-1; unit norm. nullopt for anything else
// (several stacked solutions, no model, not finite).
std::optional<Eigen::Matrix3d> FundamentalOfModel(const cv::Mat& model,
                                                  const std::optional<PinholeIntrinsics>& K);

// The RANSAC epipolar model of the pixel matches p0[i] -> p1[i] (the point tracker's outlier
// rejection and the line tracker's gate): with K the essential matrix (five-point), without it
// the fundamental matrix (eight-point); threshold in pixels; inliers: optional mask per match.
// The points are passed through to OpenCV as they are (float or double). Read the model with
// FundamentalOfModel.
cv::Mat EpipolarModel(cv::InputArray p0, cv::InputArray p1,
                      const std::optional<PinholeIntrinsics>& K, double threshold_px,
                      double confidence, cv::OutputArray inliers = cv::noArray());

}  // namespace vision
}  // namespace plucker
