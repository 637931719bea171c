// The inputs of `plucker vio`: a features folder (the sim format, docs/sim-format.md) or a EuRoC
// folder (cam0 images undistorted and fed to the image front end, imu0), as the window's per-frame
// input with the sensors it needs. The front end's stage times are measured here (the libraries
// read no clock).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/se3.h"
#include "plucker/sensor/imu.h"
#include "plucker/vision/image_frontend.h"
#include "plucker/window/sliding_window_estimator.h"

namespace plucker {
namespace app {

struct VioInput {
  std::string source;   // the folder, for messages
  PinholeIntrinsics K;  // of the (undistorted) observations
  SE3d T_b_c;
  sensor::ImuModel imu_model;
  double gravity_magnitude = 9.81;
  double pixel_sigma = 1.0;
  std::vector<window::FrameInput> frames;  // increasing times (IMU clock)
  std::vector<sensor::ImuSample> imu;
  std::vector<nlohmann::json> info;           // per frame, from the front end (empty for features)
  std::vector<std::string> warnings;          // skipped frames, IMU gaps, dropped images
  nlohmann::json frontend_ms;                 // mean per frame by stage (EuRoC)
  double frontend_cpu_ms = 0.0;               // total
  std::optional<std::vector<SE3d>> gt_T_w_b;  // per frame, for the plot only
};

// Features folder; point tracks kept when id % point_stride == 0. Throws io::IoError.
VioInput ReadVioFeatures(const std::string& dir, int point_stride);

// EuRoC folder (with mav0/ or mav0 itself): frames the IMU does not cover, repeated timestamps
// and missing or unreadable images are skipped and named in `warnings`. Throws io::IoError.
VioInput ReadVioEuroc(const std::string& dir, const vision::ImageFrontendOptions& frontend,
                      bool quiet);

}  // namespace app
}  // namespace plucker
