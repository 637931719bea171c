#include "vo_image_input.h"

#include "plucker/io/camera_calibration.h"
#include "plucker/io/image_folder.h"
#include "plucker/io/io_error.h"

namespace plucker {
namespace app {

std::vector<window::FrameInput> VoFeatureFrames(const sensor::CameraImuSequence& seq, int stride) {
  std::vector<window::FrameInput> frames(seq.frame_times.size());
  for (std::size_t i = 0; i < frames.size(); ++i) frames[i].time = seq.frame_times[i];
  for (const auto& p : seq.points)
    if (p.point_id >= 0 && p.point_id % stride == 0) frames[p.frame].points.push_back(p);
  for (const auto& s : seq.segments) frames[s.frame].segments.push_back(s);
  return frames;
}

VoImageFolder OpenVoImages(const VoImageSource& s) {
  VoImageFolder folder;
  folder.files = io::ListImageFiles(s.images);
  if (!s.sensor.empty()) {
    folder.camera = io::ReadEurocCamera(s.sensor).camera;
    return folder;
  }
  const cv::Mat first = io::ReadGrayImage(folder.files.front());
  folder.camera = io::ReadKittiCalibration(s.calib, first.cols, first.rows).camera;
  return folder;
}

cv::Mat ReadVoImage(const std::string& path, const sensor::Camera& camera, std::string* problem) {
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
  return image;
}

}  // namespace app
}  // namespace plucker
