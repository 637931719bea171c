// A EuRoC ASL folder as the input of visual-inertial odometry: the cam0 frames, their
// calibration and the IMU recording, checked against each other (formats:
// ../shared/data/README.md and io/euroc_imu.h, io/camera_calibration.h).
//   mav0/cam0/data.csv     `timestamp [ns],filename` per image, the images in mav0/cam0/data/
//   mav0/cam0/sensor.yaml  intrinsics, radial-tangential distortion, T_BS = T_b_c
//   mav0/imu0/...          io/euroc_imu.h
//
// What cannot be used is dealt with as safely as it allows:
//   - a malformed data.csv row, a calibration missing a field, an IMU log that does not parse, and
//     camera times that do not overlap the IMU's at all: IoError naming the file and the problem;
//   - a frame whose timestamp repeats or goes back, whose image file is missing, or that the IMU
//     does not cover (before its first sample, after its last, or inside a gap): skipped, with
//     the row and the reason in `skipped`;
//   - IMU gaps and dropped images (a step between listed images well above the median):
//     `warnings`, the frames kept.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "plucker/io/camera_calibration.h"
#include "plucker/io/euroc_imu.h"

namespace plucker {
namespace io {

struct EurocFrame {
  double t = 0.0;     // s since the IMU's first timestamp (EurocImuRecording::origin_ns)
  std::string image;  // path of the image file
  int line = 0;       // its row in data.csv, for messages
};

// A frame that cannot be used, structured (callers name the frame their own way): the file that
// lists it, its row there (or its index: callers with their own layout say which), the reason.
struct FrameSkip {
  std::string file;
  int line = 0;
  std::string reason;
  double t = std::numeric_limits<double>::quiet_NaN();  // the frame's time, s (NaN: unread)
  std::string ToString() const;                         // "FILE:LINE: reason"
};

struct EurocDatasetOptions {
  double max_imu_gap_s = 0.05;        // a larger step between IMU samples is a gap (EuRoC: 5 ms)
  double dropped_frame_factor = 1.5;  // a camera step above this x the median means dropped images
};

struct EurocDataset {
  EurocCamera cam0;
  EurocImuRecording imu;
  std::vector<EurocFrame> frames;     // usable frames, in time order
  std::vector<FrameSkip> skipped;     // one per skipped frame (data.csv, its row, the reason)
  std::vector<std::string> warnings;  // IMU gaps, dropped images (naming the file)
};

// `dir`: the dataset folder (with mav0/) or mav0 itself. Throws IoError.
EurocDataset ReadEurocDataset(const std::string& dir, const EurocDatasetOptions& options = {});

// The steps of the checks, for tests and other layouts: the rows of a cam0 data.csv (`name` and
// `image_dir` name the file and the image folder; rows that cannot be used go to *skipped), and
// the coverage of the frames by the IMU (frames not covered are removed and recorded with
// camera_name and their `line`; warnings name imu_name).
std::vector<EurocFrame> ParseEurocCameraCsv(const std::string& text, const std::string& name,
                                            const std::string& image_dir, std::int64_t origin_ns,
                                            std::vector<FrameSkip>* skipped);
void CheckImuCoverage(const std::vector<sensor::ImuSample>& imu, const EurocDatasetOptions& options,
                      const std::string& camera_name, const std::string& imu_name,
                      std::vector<EurocFrame>* frames, std::vector<FrameSkip>* skipped,
                      std::vector<std::string>* warnings);
// Strings of skips (ToString), for messages and bindings.
std::vector<std::string> ToStrings(const std::vector<FrameSkip>& skips);

}  // namespace io
}  // namespace plucker
