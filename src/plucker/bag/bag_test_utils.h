// Helpers of the bag layer's tests (ROS 1 and ROS 2 readers alike).
#pragma once

#include <string>

#include "plucker/bag/bag_reader.h"
#include "plucker/sensor/lidar_scan.h"

namespace plucker {
namespace bag {
namespace testing {

// A small scan whose points depend on k (5 points, intensities 1..5).
inline sensor::LidarScan Scan(int k) {
  sensor::LidarScan s;
  for (int i = 0; i < 5; ++i) s.points.emplace_back(i + k, 0.5 * i, -0.25 * k);
  s.intensity = {1, 2, 3, 4, 5};
  return s;
}

// The BagError opening `path` gives ("" when it opens).
inline std::string ErrorOf(const std::string& path) {
  try {
    BagReader r(path);
  } catch (const BagError& e) {
    return e.what();
  }
  return "";
}

}  // namespace testing
}  // namespace bag
}  // namespace plucker
