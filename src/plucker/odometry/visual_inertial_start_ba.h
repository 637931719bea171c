// The visual-inertial bundle adjustment of the dynamic start (VisualInertialOdometryOptions
// init_ba_iterations > 0): right after the linear alignment (visual_inertial_alignment.h), one
// solve over all the alignment's keyframes of their poses, velocities and biases, the landmarks
// (points and lines) triangulated from the aligned poses, the IMU preintegration factors between
// them and a weak prior on the first keyframe's accelerometer bias. The gauge is the first
// keyframe's position and yaw only: its roll and pitch (the gravity direction) are solved for,
// which the linear alignment gets tilted when the take-off barely excites the IMU (its
// accelerometer bias then absorbs the tilt; docs/results/vio.md, MH_05). The window then starts
// on the refined states. No I/O, no printing, no timing.
#pragma once

#include <vector>

#include "plucker/odometry/visual_inertial_initializer.h"
#include "plucker/odometry/visual_inertial_odometry.h"

namespace plucker {
namespace odometry {

// Refines the dynamic start in place (its candidate and second states and the poses of the
// frames up to the second: keyframes from the solve, the frames between localized against its
// map). frames: every frame so far (index = frame number); imu: covering them.
// ok false (too few keyframes or landmarks): the start is left as it was.
StartAdjustmentSummary AdjustDynamicStart(const VisualInertialOdometryOptions& options,
                                          const VisualInertialCalibration& calibration,
                                          const std::vector<window::FrameInput>& frames,
                                          const std::vector<sensor::ImuSample>& imu,
                                          VioStart* start);

}  // namespace odometry
}  // namespace plucker
