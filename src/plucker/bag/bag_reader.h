// ROS 1 bags read with Debian's rosbag_storage (no ROS master, nothing to source) and ROS 2
// `.db3` bags read with SQLite3 and the layer's CDR decoder (cdr.h): what a bag
// holds (`plucker bag info`), and a stream over chosen topics in time order whose messages are
// decoded into plucker's sensor types. Streaming: the bag's index is in memory (a few tens of
// bytes per message), message data is read one message per topic at a time.
//
// Errors name the file and the problem; message errors also the topic and the message index (its
// position in the topic, from 0, in receive order).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "plucker/sensor/imu.h"
#include "plucker/sensor/lidar_scan.h"

namespace plucker {
namespace bag {

class BagError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

constexpr const char* kPointCloud2 = "sensor_msgs/PointCloud2";
constexpr const char* kImu = "sensor_msgs/Imu";
constexpr const char* kImage = "sensor_msgs/Image";
constexpr const char* kCompressedImage = "sensor_msgs/CompressedImage";

// Which time orders the stream (and is the message's stamp): the header stamp the driver set, or
// the time the recorder received the message.
enum class StampSource { kHeader, kReceive };
StampSource StampSourceFromName(const std::string& name);  // "header" | "receive"; BagError

struct TopicInfo {
  std::string topic;
  std::string type;  // "a | b" when connections of the topic disagree
  std::size_t messages = 0;
  double first_s = 0.0, last_s = 0.0;  // receive times
};

struct BagInfo {
  std::string path;
  std::uint64_t bytes = 0;
  int version = 0;  // 200 for "#ROSBAG V2.0"; 0 for a ROS 2 bag
  std::string format = "ROS 1 bag";
  std::size_t messages = 0;
  double start_s = 0.0, end_s = 0.0;  // receive times
  std::vector<TopicInfo> topics;      // sorted by name
};

// An 8-bit gray image (row-major, no padding).
struct GrayImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;
};

// The message the stream is at.
struct MessageRef {
  std::string topic, type;
  std::size_t index = 0;  // in its topic, from 0 (receive order)
  double receive_s = 0.0, header_s = 0.0;
  double stamp_s = 0.0;  // the one of the chosen StampSource
  // The same times in integer nanoseconds (exact: differences of them are what a folder's
  // timestamp [ns] columns give).
  std::int64_t receive_ns = 0, header_ns = 0, stamp_ns = 0;
};

struct StreamStats {
  std::size_t messages = 0;      // delivered by Next
  std::size_t unreadable = 0;    // skipped: could not be read or deserialised (warnings())
  std::size_t out_of_order = 0;  // delivered with a stamp older than its topic's previous one
};

struct TopicRequest {
  std::string topic;
  std::vector<std::string> types;  // accepted message types (e.g. {kImage, kCompressedImage})
};

class BagReader {
 public:
  // Opens and indexes the bag: a ROS 1 `.bag`, a ROS 2 `.db3` (SQLite3, CDR payloads) or a
  // rosbag2 folder (metadata.yaml and one .db3), picked by the content. Throws BagError: no such
  // file, not a bag (an MCAP is named as such), unindexed (how to reindex), truncated, not a
  // rosbag2 database, or unreadable.
  explicit BagReader(const std::string& path);
  ~BagReader();
  BagReader(const BagReader&) = delete;
  BagReader& operator=(const BagReader&) = delete;

  const BagInfo& info() const;
  const std::string& path() const;

  // Starts a stream over the requested topics. Throws BagError for a topic the bag lacks (the
  // message lists the topics it has) or one of another type.
  void Select(const std::vector<TopicRequest>& topics, StampSource stamp = StampSource::kHeader);

  // Moves to the next message in stamp order across the selected topics (ties: the order of the
  // requests; within a topic, receive order). False at the end. Unreadable messages are skipped
  // and counted.
  bool Next(MessageRef* message);

  // Decode the current message. False with *error = "<file>: topic T, message i: <problem>" when
  // it is of another type or its content is not supported (the caller skips and counts it).
  bool ReadScan(sensor::LidarScan* scan, std::string* error) const;   // PointCloud2
  bool ReadImu(sensor::ImuSample* sample, std::string* error) const;  // Imu
  // Image (mono8, bgr8, rgb8, bgra8, rgba8 converted to gray with OpenCV's weights).
  bool ReadImage(GrayImage* image, std::string* error) const;
  // CompressedImage: the encoded bytes and their format ("jpeg", "png", ...), not decoded here.
  bool ReadCompressed(std::string* format, std::vector<std::uint8_t>* bytes,
                      std::string* error) const;

  const StreamStats& stats() const;
  const std::vector<std::string>& warnings() const;  // one per unreadable message (first 100)

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bag
}  // namespace plucker
