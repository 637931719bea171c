// `plucker vio --tracks DIR`: the window's input observations of every frame with a pose, as the
// simulator's rows (docs/sim-format.md), in the undistorted pixels of the pipeline's pinhole:
// DIR/points.txt `frame point_id u v`, DIR/segments.txt `frame line_id su sv eu ev`, and
// DIR/window_lines.txt `frame line_id` (the lines in the window's map when the frame's pose was
// set), DIR/frames.txt `frame t fx fy cx cy` (t: the frame's time in seconds, on the dataset's
// clock when the input has one, as the TUM output). To measure the front end's tracks against a
// ground truth (scripts/vio_track_residuals.py). Written at the end of the run, frames in index
// order.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "plucker/odometry/visual_inertial_odometry.h"

namespace plucker {
namespace app {

class VioTrackWriter {
 public:
  // The writer becomes vio's frame observer (vio outlives the writer's use).
  explicit VioTrackWriter(odometry::VisualInertialOdometry* vio);
  // Creates dir and writes the four files; throws io::IoError naming a file it cannot write.
  void Write(const std::string& dir, std::optional<std::int64_t> clock_origin_ns) const;

 private:
  const odometry::VisualInertialOdometry* vio_;
  std::map<int, window::FrameInput> frames_;  // by frame index
  std::map<int, std::vector<int>> window_lines_;
};

}  // namespace app
}  // namespace plucker
