// The inputs of `plucker vo`: a features folder's frames, or a folder of images (name order) and
// its calibration, read one image at a time (the pipeline, odometry/monocular_odometry.h,
// undistorts and runs the front end).
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "plucker/sensor/camera.h"
#include "plucker/sensor/camera_imu_sequence.h"
#include "plucker/window/sliding_window_estimator.h"

namespace plucker {
namespace app {

// The frames of a features folder's sequence; point tracks kept when id % stride == 0.
std::vector<window::FrameInput> VoFeatureFrames(const sensor::CameraImuSequence& seq, int stride);

struct VoImageSource {
  std::string images;  // folder
  std::string calib;   // KITTI calib.txt (P0), or
  std::string sensor;  // EuRoC cam0 sensor.yaml (radial-tangential: images are undistorted)
  double frame_rate_hz = 10.0;  // frame times i / rate (the folder has none)
};

struct VoImageFolder {
  std::vector<std::string> files;  // name order
  sensor::Camera camera;           // of the raw images (KITTI: pinhole of the first image's size)
};

// Throws io::IoError for a folder without images or a calibration that does not parse.
VoImageFolder OpenVoImages(const VoImageSource& source);

// The raw 8-bit image, or an empty one with the reason it cannot be used (unreadable, or of
// another size than the calibration's) in *problem.
cv::Mat ReadVoImage(const std::string& path, const sensor::Camera& camera, std::string* problem);

}  // namespace app
}  // namespace plucker
