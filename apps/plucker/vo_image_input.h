// The inputs of `plucker vo`: a features folder's frames, or a stream of raw images and their
// calibration (camera_input.h) from a folder of images (name order, frame times i / rate) or the
// image topic of a ROS 1 bag (bag_sensor_input.h, frame times from the stamps), read one image
// at a time (the pipeline, odometry/monocular_odometry.h, undistorts and runs the front end).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "bag_sensor_input.h"
#include "camera_input.h"
#include "plucker/sensor/camera.h"
#include "plucker/sensor/camera_imu_sequence.h"
#include "plucker/window/sliding_window_estimator.h"

namespace plucker {
namespace app {

struct VoImageSource {
  std::string images;           // a folder of images, or
  BagFlags bag;                 // or a bag's image topic
  CameraFlags camera;           // --sensor, --calib (KITTI calib.txt or Kalibr camchain)
  double frame_rate_hz = 10.0;  // folders: frame times i / rate (the folder has none)
};

// std::invalid_argument unless exactly one of --features, --images, --bag is given, with a
// camera flag for images (none for features), and --draw (non-empty) only with --images.
void CheckVoSources(const std::string& features, const VoImageSource& images,
                    const std::string& draw);

struct VoImage {
  double t = 0.0;       // s (bags: since the first image's stamp)
  cv::Mat image;        // raw 8-bit gray; empty when it cannot be used (problem says why)
  std::string name;     // the file, or "BAG: topic T, message i"
  std::string problem;  // unreadable, undecodable, or of another size than the calibration
};

class VoImageStream {
 public:
  // Opens the folder or bag and reads the calibration (the first image gives the size KITTI
  // files lack). Throws io::IoError, bag::BagError, std::invalid_argument.
  explicit VoImageStream(const VoImageSource& source);
  ~VoImageStream();

  const sensor::Camera& camera() const { return camera_; }
  const std::string& source() const { return source_; }
  std::size_t size() const;   // frames expected (the folder's files, the topic's messages)
  bool Next(VoImage* image);  // false at the end
  std::vector<std::string> warnings() const;  // bags: messages dropped (not delivered)

 private:
  sensor::Camera camera_;
  std::string source_;
  std::vector<std::string> files_;  // a folder
  std::size_t next_ = 0;
  double rate_hz_ = 10.0;
  std::unique_ptr<BagSensorStream> bag_;
  std::optional<VoImage> first_;  // a bag's first image, read for the size
  std::int64_t first_ns_ = 0;
};

}  // namespace app
}  // namespace plucker
