// Writes ROS 1 bags with rosbag_storage, or ROS 2 `.db3` bags (SQLite3, CDR payloads; a path
// ending in .db3) with the same calls: LiDAR scans as sensor_msgs/PointCloud2, IMU samples as
// sensor_msgs/Imu, gray images as sensor_msgs/Image. For tests and for converting the folders
// plucker reads (`plucker bag from-lidar`, `plucker bag from-euroc`). A .db3 is a single file
// (no metadata.yaml): plucker reads it as it is; `ros2 bag reindex` makes a rosbag2 folder of it.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "plucker/bag/point_cloud.h"
#include "plucker/sensor/imu.h"
#include "plucker/sensor/lidar_scan.h"

namespace plucker {
namespace bag {

struct BagWriterOptions {
  bool lz4 = false;           // compress chunks (LZ4)
  std::string frame_id = "";  // header.frame_id of every message
  void Check() const {}
};

// True when `path` ends in .db3: BagWriter writes a ROS 2 bag there.
bool IsDb3Path(const std::string& path);

class BagWriter {
 public:
  // Creates `path`; throws BagError when it exists (nothing is overwritten) or cannot be written.
  explicit BagWriter(const std::string& path, const BagWriterOptions& options = {});
  ~BagWriter();  // closes (writes the index)
  BagWriter(const BagWriter&) = delete;
  BagWriter& operator=(const BagWriter&) = delete;

  // receive_s: the bag's record time (>= 1 ns); header_s: header.stamp (>= 0). Throws BagError.
  void WriteScan(const std::string& topic, double receive_s, double header_s,
                 const sensor::LidarScan& scan);
  void WriteCloud(const std::string& topic, double receive_s, double header_s,
                  const CloudLayout& layout, const std::vector<std::uint8_t>& data);
  void WriteImu(const std::string& topic, double receive_s, const sensor::ImuSample& sample);
  void WriteImage(const std::string& topic, double receive_s, double header_s, int width,
                  int height, const std::string& encoding, const std::vector<std::uint8_t>& data);
  // The same with integer-nanosecond stamps (exact: a EuRoC folder's timestamp [ns] columns);
  // receive_ns >= 1, header_ns >= 0. Throws BagError.
  void WriteImuNs(const std::string& topic, std::int64_t receive_ns, std::int64_t header_ns,
                  const sensor::ImuSample& sample);
  void WriteImageNs(const std::string& topic, std::int64_t receive_ns, std::int64_t header_ns,
                    int width, int height, const std::string& encoding,
                    const std::vector<std::uint8_t>& data);
  void WriteCompressed(const std::string& topic, double receive_s, double header_s,
                       const std::string& format, const std::vector<std::uint8_t>& data);
  void WriteCompressedNs(const std::string& topic, std::int64_t receive_ns, std::int64_t header_ns,
                         const std::string& format, const std::vector<std::uint8_t>& data);
  void Close();  // idempotent

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bag
}  // namespace plucker
