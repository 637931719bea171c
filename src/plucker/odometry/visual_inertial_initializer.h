// The start of the visual-inertial odometry (visual_inertial_odometry.h), fed the growing
// buffer of frames and IMU samples one frame at a time:
//   1. static test (inertial/static_initializer.h) on the IMU up to the newest frame, the image
//      motion of the frames vetoing moving blocks; it decides once the motion has started (the
//      still span is then the one the whole log would give) or at the end of the input;
//   2. static: the window starts on the first two frames of the still span at rest;
//   3. else dynamic: for start frames i in order, the first second frame j (up to 30 later)
//      whose two-view rotation agrees with the gyroscope's (init_max_rotation_disagreement_deg
//      plus init_gyro_bias_bound times their time apart), a vision-only window run on, and at
//      each keyframe from init_min_keyframes on the initialisation choice and AlignVisualInertial
//      (scale, gravity, velocities, gyro bias); a run that fails or reaches init_max_keyframes
//      restarts from a later start frame. The pairs are tried in that order; at most
//      init_pair_budget RANSACs run a frame (the rest wait for the next frames, in order; at the
//      end of the input the search runs out), and while the search is behind a pair whose
//      rotated parallax (RotatedParallax in the .cc) is under init_pair_min_rotated_parallax_px
//      is refused without its RANSAC.
// A decision at frame k uses only the inputs up to frame k: fed one frame at a time it takes the
// decision a run over the whole sequence would take, at the frame where that run's data ends.
// No I/O, no printing, no timing.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "plucker/inertial/static_initializer.h"
#include "plucker/odometry/visual_inertial_odometry.h"

namespace plucker {
namespace odometry {

// The outcome: the window's first two keyframes and their states, and the poses of the frames
// up to the second.
struct VioStart {
  std::string method;  // static | dynamic
  int first = -1, second = -1;
  sensor::BodyState state_first, state_second;
  // Earlier keyframes (dynamic), with their states: the window starts on them (or on the
  // earliest that shares enough landmarks with the second).
  std::vector<int> candidates;
  std::vector<sensor::BodyState> candidate_states;
  std::vector<std::optional<SE3d>> T_w_b;  // frames <= second
};

class VisualInertialInitializer {
 public:
  VisualInertialInitializer(const VisualInertialOdometryOptions& options,
                            const VisualInertialCalibration& calibration);
  ~VisualInertialInitializer();

  // frames: every frame so far (index = frame number), imu: every sample so far (covering the
  // newest frame), flags: the image motion of the frames (ImageMotion). Returns true once the
  // start is decided (start()); end_of_input: no more frames will come (failed() if no start).
  bool Advance(const std::vector<window::FrameInput>& frames,
               const std::vector<sensor::ImuSample>& imu,
               const std::vector<inertial::ImageMotionFlag>& flags, bool end_of_input);
  bool failed() const;
  const VioStart& start() const;
  const std::vector<VioInitEvent>& events() const;
  // The two-view RANSACs of the dynamic search so far (init_pair_budget bounds them a frame).
  int two_view_tests() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The image motion of `frame` against `previous`: the median displacement of their common point
// tracks, still when at most still_px; nullopt with fewer than 5 common tracks.
std::optional<inertial::ImageMotionFlag> ImageMotion(const window::FrameInput& previous,
                                                     const window::FrameInput& frame,
                                                     double still_px);

}  // namespace odometry
}  // namespace plucker
