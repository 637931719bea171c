// A LiDAR scan as read from disk or simulated: structure of arrays, one entry per point, in the
// sensor's firing order when the source has one. Optional channels are empty when absent.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace plucker {
namespace sensor {

struct LidarScan {
  std::vector<Eigen::Vector3d> points;  // metres, sensor frame (x forward, y left, z up)
  std::vector<float> intensity;         // same size as points, or empty
  std::vector<int> ring;                // beam index 0..N-1 (0 = lowest), or empty
  std::vector<double> time;             // seconds relative to the scan start, or empty
  double timestamp = 0.0;               // scan start time, seconds

  std::size_t size() const { return points.size(); }
  bool empty() const { return points.empty(); }
};

}  // namespace sensor

// The layers written before sensor/ existed name it plucker::LidarScan.
using sensor::LidarScan;

}  // namespace plucker
