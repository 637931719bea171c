// Odometry defaults that depend on the input sequence, shared by `plucker lidar` and
// `plucker bench lidar`.
#pragma once

#include "plucker/io/lidar_sequence.h"
#include "plucker/lidar/odometry.h"

namespace plucker {
namespace app {

// PCD recordings guarantee no firing order: with ring_source kAuto, scans without a ring field
// get their rings from the elevation table instead of the point order (KITTI .bin).
inline void AdaptToSequence(const io::LidarSequence& seq, lidar::LidarOdometryOptions* options) {
  if (seq.format() == io::LidarSequence::Format::kPcd &&
      options->ring_source == lidar::RingSource::kAuto)
    options->ring_source = lidar::RingSource::kAutoElevation;
}

}  // namespace app
}  // namespace plucker
