// The KITTI odometry metric, as defined by the official devkit (evaluate_odometry.cpp):
//   dist[i]   ground-truth path length from frame 0 to frame i;
//   starts    first = 0, 10, 20, ... (step size 10 frames, i.e. one second at 10 Hz);
//   ends      for each length len in {100, 200, ..., 800} m: last = the first frame i >= first
//             with dist[i] > dist[first] + len (STRICTLY greater, as the devkit's
//             lastFrameFromSegmentLength); no such frame -> no segment for (first, len);
//   error     G = inv(gt[first]) gt[last], P = inv(est[first]) est[last], E = inv(P) G;
//             t_err = |t(E)| / len,  r_err = acos(max(min((trace(R(E)) - 1) / 2, 1), -1)) / len;
//   result    the plain average over all segments (every length and start weighs the same),
//             reported as t_err in % and r_err in deg/m and deg/100 m; per-length averages too.
// The devkit stores distances as float; this uses double (results agree to float precision
// except for a path distance that ties a length within float rounding).
#pragma once

#include <optional>
#include <vector>

#include "plucker/geometry/se3.h"

namespace plucker {
namespace eval {

struct KittiOptions {
  std::vector<double> lengths = {100, 200, 300, 400, 500, 600, 700, 800};  // metres
  int step_size = 10;                                                      // frames
  double frame_rate_hz = 10.0;  // only for the reported segment speed
};

struct KittiSegment {
  int first = 0;
  int last = 0;
  double length = 0.0;             // metres
  double translation_error = 0.0;  // |t(E)| / len (ratio; x100 for %)
  double rotation_error = 0.0;     // angle(R(E)) / len, rad/m
  double speed = 0.0;              // len / ((last - first + 1) / frame_rate), m/s (as devkit)
};

struct KittiLengthResult {
  double length = 0.0;
  int segment_count = 0;
  // std::nullopt when no segment of this length fits in the sequence.
  std::optional<double> translation_error_percent;
  std::optional<double> rotation_error_deg_per_100m;
};

struct KittiResult {
  int pose_count = 0;
  double path_length = 0.0;  // ground-truth path length, metres
  int segment_count = 0;
  // std::nullopt when no segment fits ("no segment": the path is shorter than the shortest
  // length). Never 0 or NaN in that case.
  std::optional<double> translation_error_percent;
  std::optional<double> rotation_error_deg_per_m;
  std::optional<double> rotation_error_deg_per_100m;
  std::vector<KittiLengthResult> per_length;
  std::vector<KittiSegment> segments;
  std::vector<double> distance;  // dist[i], metres

  bool has_segments() const { return segment_count > 0; }
};

// gt and est: one pose a frame (T_cam0(0)_cam0(i)), same sizes. Throws std::invalid_argument if
// the sizes differ or are zero, or the options are invalid.
KittiResult ComputeKittiMetric(const std::vector<SE3d>& gt, const std::vector<SE3d>& est,
                               const KittiOptions& options = {});

// The devkit's rotation error of a 3x3 rotation: acos(max(min((trace - 1) / 2, 1), -1)).
double DevkitRotationAngle(const Eigen::Matrix3d& R);

}  // namespace eval
}  // namespace plucker
