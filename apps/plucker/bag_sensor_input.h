// The camera (and IMU) topics of a ROS 1 bag as the input of `plucker vo --bag` and `plucker vio
// --bag`: a stream of images and IMU samples in the order of the chosen stamps (bag/bag_reader.h:
// header or receive), one message in memory at a time. Images: sensor_msgs/Image (mono8, 8UC1,
// bgr8, rgb8, bgra8, rgba8, converted to gray) or sensor_msgs/CompressedImage (decoded with
// OpenCV). What cannot be used is skipped and named (file, topic, message index): a message
// that does not deserialise, an encoding that is not supported, an image that does not decode
// (delivered with `problem` set, so that the frame counts as skipped), a stamp that does not
// increase within its topic (dropped: the estimators need increasing times).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <opencv2/core.hpp>

#include "plucker/bag/bag_reader.h"
#include "plucker/sensor/imu.h"

namespace plucker {
namespace app {

// The flags of a bag input: --bag FILE, --image-topic T, --imu-topic T (imu), --stamp
// header|receive. Returns the --bag option.
struct BagFlags {
  std::string bag, image_topic, imu_topic, stamp = "header";
};
CLI::Option* AddBagFlags(CLI::App* cmd, BagFlags* flags, bool imu, const std::string& bag_help);

struct BagItem {
  bool is_imu = false;
  std::int64_t stamp_ns = 0;  // of the chosen stamp source
  sensor::ImuSample imu;      // is_imu; t = stamp in s (absolute)
  cv::Mat image;              // !is_imu: 8-bit gray (empty when `problem` is set)
  std::string name;           // "BAG: topic T, message i", for messages and the JSON
  std::string problem;        // !is_imu: why the image cannot be used (it is skipped)
};

class BagSensorStream {
 public:
  // imu_topic empty: images only. Throws bag::BagError for a bag that cannot be read, a topic it
  // lacks (the message lists the ones it has) or one of another type, --stamp other than
  // header|receive.
  BagSensorStream(const std::string& path, const std::string& image_topic,
                  const std::string& imu_topic, const std::string& stamp);
  ~BagSensorStream();

  // The next image or IMU sample in stamp order; false at the end.
  bool Next(BagItem* item);

  const std::string& path() const;
  std::size_t image_messages() const;  // on the image topic (bag info)
  // The stamp of the first message of a topic in stream order (a pass over it alone); nullopt
  // when the topic has no readable message.
  std::optional<std::int64_t> FirstStampNs(const std::string& topic);
  // Unreadable and dropped messages (the bag's and this stream's), one line each (first 100).
  std::vector<std::string> warnings() const;
  std::size_t dropped() const;  // messages skipped by the stream (not delivered)

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace app
}  // namespace plucker
