// sensor_msgs/PointCloud2 as plain data, and its conversion to a LiDAR scan. Kept free of ROS
// types so that the layout rules are tested without a bag.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "plucker/sensor/lidar_scan.h"

namespace plucker {
namespace bag {

// sensor_msgs/PointField datatypes.
enum class FieldType : std::uint8_t {
  kInt8 = 1,
  kUint8 = 2,
  kInt16 = 3,
  kUint16 = 4,
  kInt32 = 5,
  kUint32 = 6,
  kFloat32 = 7,
  kFloat64 = 8
};

struct CloudField {
  std::string name;
  std::uint32_t offset = 0;   // bytes from the start of the point
  std::uint8_t datatype = 0;  // FieldType
  std::uint32_t count = 1;
};

struct CloudLayout {
  std::uint32_t width = 0, height = 1;
  std::uint32_t point_step = 0, row_step = 0;  // bytes
  bool big_endian = false;
  std::vector<CloudField> fields;
};

// Counts of what CloudToScan dropped.
struct CloudStats {
  std::size_t points = 0;              // width * height
  std::size_t non_finite_dropped = 0;  // a NaN/Inf coordinate
};

// Fills *scan from a PointCloud2's layout and data, as the PCD reader does: x, y, z required (any
// numeric type), `intensity` and `ring` when present, the per-point time from `time`, `t` or
// `timestamp` (float fields in seconds, integer fields in nanoseconds; times are made relative to
// the earliest point, whose absolute time, when it is one (> 1 s), becomes scan->timestamp).
// Points with a non-finite coordinate are dropped. Any field order and point step; little-endian
// only. Returns "" on success, else the problem (the caller names the file, topic and message).
std::string CloudToScan(const CloudLayout& layout, const std::uint8_t* data, std::size_t size,
                        sensor::LidarScan* scan, CloudStats* stats = nullptr);

// The layout CloudToScan reads back into the same scan: float32 x y z [intensity] [float64 time]
// [uint16 ring], one row, packed. The writer uses it.
CloudLayout ScanLayout(const sensor::LidarScan& scan);
void ScanToCloudData(const sensor::LidarScan& scan, const CloudLayout& layout,
                     std::vector<std::uint8_t>* data);

}  // namespace bag
}  // namespace plucker
