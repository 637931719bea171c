// The frame observer of the online pipelines (MonocularOdometry, VisualInertialOdometry): called
// for a frame once its pose is set, with the window's map as it is then (e.g. to draw the frame's
// observations and the landmarks over its image: `plucker vo --draw`, `plucker vio --draw`).
#pragma once

#include <functional>

#include "plucker/geometry/se3.h"
#include "plucker/window/sliding_window_estimator.h"

namespace plucker {
namespace odometry {

// frame: the index among the frames given; input: its observations (undistorted pixels of the
// pipeline's pinhole); T_w_c: the camera in the world; map: the window's landmarks.
using FrameObserver =
    std::function<void(int frame, const window::FrameInput& input, const SE3d& T_w_c,
                       const window::SlidingWindowEstimator& map)>;

}  // namespace odometry
}  // namespace plucker
