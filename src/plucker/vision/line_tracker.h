// Line segment tracks over an image sequence. For every new frame:
//   1. describe: LBD descriptors of the frame's segments (line_matcher.h; clipped, oriented);
//   2. continue: match the tracks seen in the previous frame against the new segments
//      (MatchLines with the epipolar gate when the caller passes F_cur_prev, e.g. from the point
//      tracks: FundamentalFromPointTracks, and with the prediction gate: flow_samples points
//      along each track's segment are followed into the new image by pyramidal Lucas-Kanade,
//      whose displacement across the edge is well defined);
//   3. re-associate: a track not found in a frame coasts on its flow prediction (its segment
//      moves with the followed points) for up to max_lost_frames frames and takes part in the
//      matching of step 2 from there, so a track may skip a frame or two (occlusion, a missed
//      detection) under the same gates; a track that cannot be followed by flow ends;
//   4. start: every segment still free starts a new track.
// Track ids are never reused; a track's appearance is its latest descriptor. Output per frame:
// every described segment as sensor::SegmentObservation with line_id = its track id (the form of
// the simulator and the estimators; a consumer keeps the tracks it needs, e.g. 3+ views).
// No I/O, no timing.
#pragma once

#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/se3.h"
#include "plucker/sensor/camera_observations.h"
#include "plucker/vision/flow_pyramid.h"
#include "plucker/vision/line_matcher.h"

namespace plucker {
namespace vision {

struct LineTrackerOptions {
  LineDescriberOptions describe;
  LineMatcherOptions match;  // frame to frame
  int max_lost_frames = 2;   // a track may skip this many frames and be re-associated
  int flow_samples = 5;      // points per segment followed by optical flow (0: no prediction gate)
  int flow_window_px = 11;   // 15 before: MH05 clip, docs/results/frontend-speed.md
  int flow_levels = 3;
  // Gauss-Newton steps per level of the flow. Points on an edge converge across it in a few
  // steps; along it the flow is undefined and would use all 30 of OpenCV's default, for a
  // component the prediction gate does not use.
  int flow_iterations = 8;
  // A track and a segment that are each other's only candidate under every gate, the flow
  // prediction included, are matched without descriptors (the Hamming distance is not checked);
  // LBD descriptors are computed only for the tracks and segments with several candidates. A
  // track's descriptor is that of its latest observation, computed when it is needed in the
  // image of that frame (the last max_lost_frames + 1 images are kept). false: every gated pair
  // is checked by its descriptors (the same matches as MatchLines on all segments).
  bool flow_first = true;
};

struct LineTrackerStats {
  LineDescriptionStats description;
  LineMatchStats match;        // of step 2
  int predicted = 0;           // previous-frame tracks with a flow prediction
  int continued = 0;           // tracks seen in the previous frame and in this one
  int reassociated = 0;        // tracks lost for 1..max_lost_frames frames, found again
  int started = 0;             // new tracks
  int lost = 0;                // tracks of the previous frame not found (kept for re-association)
  int ended = 0;               // tracks dropped for good (lost longer than max_lost_frames)
  int flow_matched = 0;        // matches of a unique flow-gated pair (no descriptors)
  int lbd_described = 0;       // LBD descriptors computed in this frame (segments and tracks)
  bool epipolar_gate = false;  // F_cur_prev was given
};

struct LineTrackerFrame {
  int frame = 0;                                         // 0-based index of Track() calls
  std::vector<sensor::SegmentObservation> observations;  // frame = this frame, line_id = track
  LineTrackerStats stats;
};

class LineTracker {
 public:
  // Throws std::invalid_argument for invalid options.
  explicit LineTracker(const LineTrackerOptions& options = {});

  // gray: CV_8UC1, the size of the first frame (std::invalid_argument otherwise); segments in
  // pixels of this image (possibly none). F_cur_prev: x_cur^T F x_prev = 0.
  LineTrackerFrame Track(const cv::Mat& gray, const std::vector<Segment2d>& segments,
                         const std::optional<Eigen::Matrix3d>& F_cur_prev = std::nullopt);
  // The same on the frame's flow pyramid (flow_pyramid.h; e.g. the one the point tracker used):
  // its window_px must be >= flow_window_px (std::invalid_argument otherwise); the flow uses
  // min(flow_levels, pyramid.max_level()) levels.
  LineTrackerFrame Track(const FlowPyramid& pyramid, const std::vector<Segment2d>& segments,
                         const std::optional<Eigen::Matrix3d>& F_cur_prev = std::nullopt);

  int next_track_id() const { return next_id_; }
  int live_tracks() const { return static_cast<int>(tracks_.size()); }

 private:
  struct TrackState {
    int id = -1;
    int last_frame = -1;
    Segment2d segment = Segment2d::Zero();   // latest (observed, or coasting on the flow)
    Segment2d observed = Segment2d::Zero();  // as observed in last_frame
    cv::Mat descriptor;                      // 1 x 32, CV_8UC1, of `observed` when
    int descriptor_frame = -1;               // descriptor_frame == last_frame
  };
  std::vector<LineMatch> Associate(const std::vector<int>& candidate_index,
                                   const LinePredictions& predictions, const cv::Mat& gray,
                                   const LineFeatures& current,
                                   const std::optional<Eigen::Matrix3d>& F_cur_prev,
                                   std::vector<cv::Mat>* current_descriptors, LineTrackerStats* st);
  void DescribeTracks(const std::vector<int>& track_index, LineTrackerStats* st);
  LineTrackerFrame TrackImpl(const cv::Mat& gray, const FlowPyramid& pyramid,
                             const std::vector<Segment2d>& segments,
                             const std::optional<Eigen::Matrix3d>& F_cur_prev);
  LinePredictions Predict(const std::vector<const TrackState*>& tracks, const FlowPyramid& pyramid,
                          int* predicted) const;

  LineTrackerOptions options_;
  std::vector<TrackState> tracks_;  // live and recently lost tracks
  cv::Size size_;
  FlowPyramid previous_;  // of the previous image (for the flow prediction; empty without flow)
  std::vector<std::pair<int, cv::Mat>> images_;  // (frame, image) of the latest frames
  int next_id_ = 0;
  int frame_ = 0;
};

// The fundamental matrix F_cur_prev (x_cur^T F x_prev = 0) from point tracks of two frames
// (observations with equal point_id; e.g. vision/point_tracker.h): RANSAC on the essential
// matrix when K is given (F = K^-T E K^-1), else on F. nullopt with fewer than min_points
// common tracks or when RANSAC finds no model.
std::optional<Eigen::Matrix3d> FundamentalFromPointTracks(
    const std::vector<sensor::PointObservation>& previous,
    const std::vector<sensor::PointObservation>& current, const std::optional<PinholeIntrinsics>& K,
    double threshold_px = 1.0, int min_points = 15);

// F_b_a of two posed pinhole views (T_w_a, T_w_b), e.g. from ground truth.
Eigen::Matrix3d FundamentalFromPoses(const PinholeIntrinsics& K, const SE3d& T_w_a,
                                     const SE3d& T_w_b);

}  // namespace vision
}  // namespace plucker
