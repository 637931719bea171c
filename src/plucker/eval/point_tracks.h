// Quality of point tracks against ground-truth camera poses.
//
// A track (the observations with one point_id over the frames) of at least min_views views is
// triangulated from the ground-truth cameras (geometry/point_triangulation.h, N-view DLT and
// Gauss-Newton, no parallax test) and judged by its largest reprojection error over the track:
// correct when it is within max_error_px, wrong otherwise (a point behind a camera is wrong).
// A track whose triangulation fails (rays that do not meet in front of the cameras, a degenerate
// system) is counted as `failed` and left out of the precision. Pure geometry, no images.
#pragma once

#include <vector>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/se3.h"
#include "plucker/sensor/camera_observations.h"

namespace plucker {
namespace eval {

struct PointTrackQualityOptions {
  int min_views = 2;
  double max_error_px = 2.0;
};

struct PointTrackResult {
  int point_id = -1;
  int views = 0;
  bool judged = false;        // triangulated (views >= min_views and the triangulation held)
  double max_error_px = 0.0;  // largest reprojection error over the track (judged only)
};

struct PointTrackQuality {
  int tracks = 0;     // all track ids (>= 0)
  int evaluated = 0;  // tracks of >= min_views views
  int correct = 0, wrong = 0, failed = 0;
  double precision() const {  // correct / (correct + wrong); 0 when none was judged
    return correct + wrong > 0 ? static_cast<double>(correct) / (correct + wrong) : 0.0;
  }
  std::vector<PointTrackResult> results;  // one per track, by point_id
};

// T_w_c[f]: the ground-truth pose of frame f; every observation's frame must index it
// (std::invalid_argument otherwise, naming the frame). Observations with point_id < 0 are
// ignored; invalid intrinsics or options are std::invalid_argument.
PointTrackQuality EvaluatePointTracks(const PinholeIntrinsics& K, const std::vector<SE3d>& T_w_c,
                                      const std::vector<sensor::PointObservation>& observations,
                                      const PointTrackQualityOptions& options = {});

}  // namespace eval
}  // namespace plucker
