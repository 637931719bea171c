#include "vo_image_input.h"

#include <array>
#include <iostream>
#include <memory>
#include <optional>

#include "plucker/io/camera_calibration.h"
#include "plucker/io/image_folder.h"
#include "plucker/io/io_error.h"
#include "plucker/vision/image_frontend.h"
#include "plucker/vision/undistort.h"
#include "stage_clock.h"

namespace plucker {
namespace app {
namespace {

const char* kFrontendStages[vision::kNumFrontendStages] = {"points", "detection", "lines"};

// The camera of the images and, for a distorted one, the undistorter to its ideal pinhole.
struct ImageCamera {
  PinholeIntrinsics K;
  int width = 0, height = 0;
  std::shared_ptr<vision::Undistorter> undistorter;
};

ImageCamera ReadCamera(const VoImageSource& s, const std::string& first_image) {
  ImageCamera c;
  if (!s.sensor.empty()) {
    const io::EurocCamera euroc = io::ReadEurocCamera(s.sensor);
    c.undistorter = std::make_shared<vision::Undistorter>(euroc.camera);
    c.K = c.undistorter->ideal_camera().K;
    c.width = euroc.camera.width;
    c.height = euroc.camera.height;
    return c;
  }
  const cv::Mat first = io::ReadGrayImage(first_image);
  const io::KittiCalibration calib = io::ReadKittiCalibration(s.calib, first.cols, first.rows);
  c.K = calib.camera.K;
  c.width = first.cols;
  c.height = first.rows;
  return c;
}

// The image, undistorted, or the reason it cannot be used.
cv::Mat LoadImage(const std::string& path, const ImageCamera& camera, std::string* problem) {
  cv::Mat image;
  try {
    image = io::ReadGrayImage(path);
  } catch (const io::IoError& e) {
    *problem = e.what();
    return {};
  }
  if (image.cols != camera.width || image.rows != camera.height) {
    *problem = path + ": image size " + std::to_string(image.cols) + "x" +
               std::to_string(image.rows) + " differs from the calibration's " +
               std::to_string(camera.width) + "x" + std::to_string(camera.height);
    return {};
  }
  return camera.undistorter ? camera.undistorter->Undistort(image) : image;
}

}  // namespace

VoImageInput ReadVoImages(const VoImageSource& s) {
  const std::vector<std::string> files = io::ListImageFiles(s.images);
  const ImageCamera camera = ReadCamera(s, files.front());
  VoImageInput in;
  in.K = camera.K;
  in.undistorter = camera.undistorter;
  vision::ImageFrontendOptions options = s.frontend;
  options.use_lines = s.use_lines;
  vision::ImageFrontend frontend(camera.K, options);
  std::array<double, vision::kNumFrontendStages> total{};
  double last_progress = WallMs();
  for (std::size_t i = 0; i < files.size(); ++i) {
    window::FrameInput frame;
    frame.time = static_cast<double>(i) / s.frame_rate_hz;
    nlohmann::json info = {{"image", files[i]}};
    std::string problem;
    const double t_read = ThreadCpuMs();
    const cv::Mat image = LoadImage(files[i], camera, &problem);
    info["ms"]["read"] = ThreadCpuMs() - t_read;
    if (image.empty()) {
      info["skipped"] = problem;
      in.warnings.push_back(problem);
    } else {
      BasicStageClock<vision::FrontendStage, vision::kNumFrontendStages> ms;
      const vision::ImageFrontendFrame f = frontend.Process(image, ms.Observer());
      for (int k = 0; k < vision::kNumFrontendStages; ++k) {
        info["ms"][kFrontendStages[k]] = ms.ms(k);
        total[k] += ms.ms(k);
      }
      frame.points = f.points;
      frame.segments = f.segments;
      info["observed_points"] = f.points.size();
      info["observed_segments"] = f.segments.size();
    }
    in.frames.push_back(std::move(frame));
    in.info.push_back(std::move(info));
    if (!s.quiet && (WallMs() - last_progress > 500.0 || i + 1 == files.size())) {
      last_progress = WallMs();
      std::cerr << "\rplucker vo: front end " << (i + 1) << "/" << files.size() << std::flush;
    }
  }
  if (!s.quiet) std::cerr << "\n";
  for (int k = 0; k < vision::kNumFrontendStages; ++k) {
    in.mean_stage_ms[kFrontendStages[k]] = total[k] / static_cast<double>(files.size());
  }
  return in;
}

}  // namespace app
}  // namespace plucker
