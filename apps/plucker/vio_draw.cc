#include "vio_draw.h"

#include <filesystem>

#include "vo_draw.h"

namespace plucker {
namespace app {

VioOverlayWriter::VioOverlayWriter(const std::string& dir, odometry::VisualInertialOdometry* vio)
    : dir_(dir), vio_(vio) {
  std::filesystem::create_directories(dir);
  vio->SetFrameObserver([this](int i, const window::FrameInput& frame, const SE3d& T_w_c,
                               const window::SlidingWindowEstimator& map) {
    const auto it = held_.find(i);
    if (it == held_.end()) return;  // dropped
    WriteFrameOverlay(dir_, it->second, vio_->undistorter(), vio_->K(), frame, i, T_w_c, map);
    ++written_;
    held_.erase(it);
  });
}

void VioOverlayWriter::Hold(const cv::Mat& image) {
  next_ = static_cast<int>(vio_->RefinedTrajectory().size());
  held_[next_] = image;
  if (static_cast<int>(held_.size()) > kMaxHeldImages) {
    held_.erase(held_.begin());
    ++dropped_;
  }
}

void VioOverlayWriter::Release(const odometry::VioFrameResult& result) {
  for (const odometry::VioFrameRecord& rec : result.settled) held_.erase(rec.frame);
}

void VioOverlayWriter::Refused() { held_.erase(next_); }

}  // namespace app
}  // namespace plucker
