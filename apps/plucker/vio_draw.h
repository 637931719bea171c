// `plucker vio --draw DIR`: the overlays of `plucker vo --draw` (vo_draw.h, the same palette)
// on each frame the window has a pose for, DIR/%06d.png by the frame's index (the JSON's
// `frame`). The odometry reports a frame's pose when the window runs on it, or at the start for
// the frames it buffered, so each image is held from AddImage until its frame settles: at most
// kMaxHeldImages (the oldest are dropped, undrawn, beyond that: a long wait for the start).
// Frames that settle without a pose (before the start, skipped) are not drawn.
#pragma once

#include <map>
#include <string>

#include <opencv2/core.hpp>

#include "plucker/odometry/visual_inertial_odometry.h"

namespace plucker {
namespace app {

class VioOverlayWriter {
 public:
  static constexpr int kMaxHeldImages = 256;

  // Creates dir; the writer becomes vio's frame observer (vio outlives the writer's use).
  VioOverlayWriter(const std::string& dir, odometry::VisualInertialOdometry* vio);

  // The raw image of the frame about to be given to vio (its index: frames given so far).
  void Hold(const cv::Mat& image);
  // After vio's call on it: the images of the frames it settled are released (drawn or not);
  // an image vio refused (the call threw) is released too.
  void Release(const odometry::VioFrameResult& result);
  void Refused();

  int written() const { return written_; }
  int dropped() const { return dropped_; }  // held too long: not drawn

 private:
  std::string dir_;
  const odometry::VisualInertialOdometry* vio_;
  std::map<int, cv::Mat> held_;  // by frame index
  int written_ = 0, dropped_ = 0, next_ = -1;
};

}  // namespace app
}  // namespace plucker
