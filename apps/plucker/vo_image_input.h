// The image input of `plucker vo`: a folder of images (name order) and its calibration, turned into
// the estimator's per-frame input by the visual front end (vision/image_frontend.h), with the
// front end's stage times measured here (the library reads no clock).
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "plucker/geometry/camera.h"
#include "plucker/vision/image_frontend.h"
#include "plucker/vision/undistort.h"
#include "plucker/window/sliding_window_estimator.h"

namespace plucker {
namespace app {

struct VoImageSource {
  std::string images;  // folder
  std::string calib;   // KITTI calib.txt (P0), or
  std::string sensor;  // EuRoC cam0 sensor.yaml (radial-tangential: images are undistorted)
  double frame_rate_hz = 10.0;  // frame times i / rate (the folder has none)
  bool use_lines = true;
  bool quiet = false;
  vision::ImageFrontendOptions frontend;  // use_lines is set from the field above
};

struct VoImageInput {
  PinholeIntrinsics K;  // of the (undistorted) images the observations are in
  std::vector<window::FrameInput> frames;
  std::vector<nlohmann::json> info;   // per frame: front-end ms by stage, counts, skipped reason
  std::vector<std::string> warnings;  // one per skipped image
  nlohmann::json mean_stage_ms;       // front end, per frame
  std::shared_ptr<const vision::Undistorter> undistorter;  // --sensor: distorted to ideal
};

// Throws io::IoError for a folder without images or a calibration that does not parse. An image
// that cannot be read or has another size is skipped (its frame has no observations) and named
// in `warnings`.
VoImageInput ReadVoImages(const VoImageSource& source);

}  // namespace app
}  // namespace plucker
