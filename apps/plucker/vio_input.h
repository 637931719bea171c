// The inputs of `plucker vio`: a features folder (the sim format, docs/sim-format.md) or a EuRoC
// folder (the cam0 image list, its calibration, imu0), as the sensors of the odometry and what
// a driver would deliver: IMU samples, and frames (features) or image files (EuRoC) in time
// order. The images are read one at a time by the loop of cmd_vio.cc.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "plucker/geometry/se3.h"
#include "plucker/io/euroc_dataset.h"
#include "plucker/odometry/visual_inertial_odometry.h"
#include "plucker/sensor/camera_imu_sequence.h"
#include "plucker/sensor/imu.h"

namespace plucker {
namespace app {

struct VioInput {
  std::string source;  // the folder, for messages
  odometry::VisualInertialCalibration calibration;
  std::vector<sensor::ImuSample> imu;
  std::vector<window::FrameInput> frames;  // features folder: increasing times (IMU clock)
  std::vector<io::EurocFrame> images;      // EuRoC: increasing times (IMU clock)
  std::vector<std::string> warnings;       // skipped frames, IMU gaps, dropped images
  int skipped_input_frames = 0;            // frames skipped at reading (named in `warnings`)
  // Ground truth for the plot: per frame (features), or the EuRoC states (nearest in time).
  std::optional<std::vector<SE3d>> gt_T_w_b;
  std::vector<sensor::BodyState> gt_states;
  // EuRoC: the dataset's clock, its first IMU timestamp (frame and IMU times are seconds since
  // it); the TUM files are written on that clock. Features folders: none (their own times).
  std::optional<std::int64_t> clock_origin_ns;
};

// The frames of a features folder's sequence (docs/sim-format.md): the point tracks whose id is
// >= 0 and a multiple of `stride` (outliers, id -1, left out), every segment.
std::vector<window::FrameInput> FeatureFrames(const sensor::CameraImuSequence& seq, int stride);

// The warnings for frames skipped at reading: one per run of frames on consecutive lines of a
// file skipped for the same reason ("skipped N frames, FILE:A-B (times T0-T1 s): reason"; a run
// of one: "skipped FILE:LINE: reason"), so that a gap or a late IMU start gives one line, not one
// per frame. `suffix` is appended to each; `frame_numbers`: LINE is a frame number ("FILE frame
// N", "FILE frames A-B").
std::vector<std::string> SkipWarnings(const std::vector<io::FrameSkip>& skipped,
                                      const std::string& suffix = "", bool frame_numbers = false);

// Features folder; point tracks kept when id % point_stride == 0. Throws io::IoError.
VioInput ReadVioFeatures(const std::string& dir, int point_stride);

// EuRoC folder (with mav0/ or mav0 itself): frames the IMU does not cover and repeated
// timestamps are skipped and named in `warnings`. Throws io::IoError.
VioInput ReadVioEuroc(const std::string& dir);

// The ground truth nearest each time (increasing), from gt_states (empty: none): the states
// (biases too) and their poses.
std::vector<sensor::BodyState> NearestGroundTruthStates(const VioInput& in,
                                                        const std::vector<double>& times);
std::vector<SE3d> NearestGroundTruth(const VioInput& in, const std::vector<double>& times);

}  // namespace app
}  // namespace plucker
