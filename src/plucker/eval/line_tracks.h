// Quality of line segment tracks against ground-truth camera poses.
//
// A track (the observations with one line_id over the frames) of at least min_views views is
// evaluated by triangulating its line from the ground-truth cameras (linear N-view and
// refinement on the line manifold, geometry/line_triangulation.h): it is correct when every
// endpoint of every segment of the track is within max_error_px of the reprojected infinite
// line. A track whose back-projected planes are (nearly) parallel (forward motion along the
// line, the conditioning test of the triangulation) cannot be judged that way: any line of the
// common plane reprojects onto every segment. Such tracks are counted as `unconstrained` and
// left out of the precision, which is correct / (correct + wrong). Pure geometry, no images.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/line_triangulation.h"
#include "plucker/geometry/se3.h"
#include "plucker/sensor/camera_observations.h"

namespace plucker {
namespace eval {

struct LineTrackQualityOptions {
  int min_views = 3;
  double max_error_px = 2.0;
  LineTriangulationOptions triangulation;
};

enum class TrackVerdict { kCorrect, kWrong, kUnconstrained, kShort };
const char* ToString(TrackVerdict verdict);

struct LineTrackResult {
  int line_id = -1;
  int views = 0;
  int first_frame = 0, last_frame = 0;
  TrackVerdict verdict = TrackVerdict::kShort;
  double max_error_px = 0.0;  // of the triangulated line (kCorrect / kWrong)
  std::string reason;         // kUnconstrained: the triangulation's message
};

struct LineTrackQuality {
  int observations = 0;  // segments with a track id (>= 0)
  int frames = 0;        // frames with at least one observation
  int tracks = 0;        // all track ids
  int evaluated = 0;     // tracks of >= min_views views
  int correct = 0, wrong = 0, unconstrained = 0;
  std::map<int, int> length_histogram;  // views -> number of tracks (all tracks)
  double mean_length = 0.0;             // views per track, tracks of >= min_views views
  double median_length = 0.0;
  double segments_per_frame = 0.0;  // observations in tracks of >= min_views views, per frame
  double precision() const {        // correct / (correct + wrong); 0 when none was judged
    return correct + wrong > 0 ? static_cast<double>(correct) / (correct + wrong) : 0.0;
  }
  std::vector<LineTrackResult> results;  // one per track, by line_id
};

// T_w_c[f]: the ground-truth pose of frame f; every observation's frame must index it
// (std::invalid_argument otherwise, naming the frame). Observations with line_id < 0 are ignored;
// a frame observing one track twice is std::invalid_argument.
LineTrackQuality EvaluateLineTracks(const PinholeIntrinsics& K, const std::vector<SE3d>& T_w_c,
                                    const std::vector<sensor::SegmentObservation>& observations,
                                    const LineTrackQualityOptions& options = {});

}  // namespace eval
}  // namespace plucker
