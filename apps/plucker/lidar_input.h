// The scans `plucker lidar` runs on: a folder (io::LidarSequence) or the PointCloud2 messages of
// one topic of a ROS 1 bag, in stamp order. Frame i is the i-th scan of either.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "plucker/bag/bag_reader.h"
#include "plucker/geometry/se3.h"
#include "plucker/io/lidar_sequence.h"

namespace plucker {
namespace app {

class LidarInput {
 public:
  explicit LidarInput(io::LidarSequence seq) : seq_(std::move(seq)) {}
  // Throws bag::BagError (no such topic: the message lists the bag's topics; another type).
  LidarInput(const std::string& bag, const std::string& topic, const std::string& stamp);

  std::size_t size() const;
  // Frames are read in order (a bag is a stream: i must be the previous i + 1). *stamp is the
  // frame's time (times.txt, the PCD or bag stamp, else 10 Hz from 0). False with *error set for a
  // frame to skip.
  bool Read(std::size_t i, LidarScan* scan, std::string* error, double* stamp);

  const io::LidarSequence* sequence() const { return seq_ ? &*seq_ : nullptr; }  // null: a bag
  const std::optional<SE3d>& T_cam0_velo() const;                                // a bag: none
  std::string description() const;
  // Where cam0 poses would need a calibration it lacks: why (the folder's calib.txt, or a bag).
  std::string missing_calib() const;
  std::string bag_summary() const;  // "" for a folder; counts of skipped/unreadable messages

 private:
  std::optional<io::LidarSequence> seq_;
  std::unique_ptr<bag::BagReader> bag_;
  std::string topic_;
  std::size_t bag_messages_ = 0;
  std::optional<SE3d> no_calib_;
};

}  // namespace app
}  // namespace plucker
