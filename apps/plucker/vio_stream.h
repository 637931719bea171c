// What the loop of `plucker vio` feeds the odometry, in the order a driver delivers it: the IMU
// samples up to a frame's time (the first sample at or after it included: the driver waits for
// the IMU to reach the image's timestamp) before the frame, then the frame; the samples after
// the last frame at the end. From a folder (features, EuRoC: VioInput) or a ROS 1 bag (one
// message in memory at a time, images held only while the IMU has not reached them).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <opencv2/core.hpp>

#include "bag_sensor_input.h"
#include "camera_input.h"
#include "vio_input.h"

namespace plucker {
namespace app {

struct VioItem {
  bool is_imu = false;
  sensor::ImuSample imu;  // is_imu
  std::size_t frame = 0;  // folders: the index into VioInput::frames / images
  double t = 0.0;         // the frame's time (s since the clock origin, IMU clock)
  std::string name;       // EuRoC: the image file; bag: "BAG: topic T, message i"
  cv::Mat image;          // bag: the decoded image (EuRoC: read by the loop from `name`)
  std::string problem;    // bag: why the image cannot be used (the frame is skipped)
};

class VioStream {
 public:
  virtual ~VioStream() = default;
  virtual bool Next(VioItem* item) = 0;    // false at the end
  virtual std::size_t frames() const = 0;  // expected frames, for progress
  // Messages the source dropped (bags: unreadable, non-increasing stamps), one line each.
  virtual std::vector<std::string> warnings() const { return {}; }
};

// The frames and IMU samples of a folder's VioInput (which must outlive the stream).
std::unique_ptr<VioStream> MakeFolderVioStream(const VioInput& in);

using VioBagSource = BagFlags;  // --bag, --image-topic, --imu-topic, --stamp

// A bag: *in gets the calibration of `calib` (its T_b_c and IMU model required), the bag as
// source and the first IMU stamp as clock origin (times are seconds since it, the camera's
// shifted by timeshift_cam_imu). Throws bag::BagError / io::IoError / std::invalid_argument.
std::unique_ptr<VioStream> OpenVioBag(const VioBagSource& source, const CameraCalibration& calib,
                                      VioInput* in);

// std::invalid_argument unless exactly one of --features, --euroc, --bag is given, and no
// calibration flag with --features (its rig.txt is the calibration).
void CheckVioSources(const std::string& features, const std::string& euroc, const VioBagSource& bag,
                     const CameraFlags& camera);

// --euroc with --sensor/--calib/--imu-sensor/--imu-calib: the given files replace the folder's
// sensor.yaml files; a Kalibr timeshift_cam_imu moves the frame times (t_imu = t_cam + shift)
// and the IMU coverage is checked again (frames no longer covered are skipped and named).
void ReplaceVioCalibration(const CameraCalibration& calib, VioInput* in);

// The input the flags name: a bag (OpenVioBag), else a features folder (tracks whose id is a
// multiple of point_stride) or a EuRoC folder with the calibration flags applied
// (ReplaceVioCalibration), streamed (MakeFolderVioStream over *in).
std::unique_ptr<VioStream> OpenVioInput(const std::string& features, const std::string& euroc,
                                        const VioBagSource& bag, const CameraFlags& camera,
                                        int point_stride, VioInput* in);

}  // namespace app
}  // namespace plucker
