#include "lidar_input.h"

#include <filesystem>

namespace plucker {
namespace app {

LidarInput::LidarInput(const std::string& bag, const std::string& topic, const std::string& stamp)
    : bag_(std::make_unique<bag::BagReader>(bag)), topic_(topic) {
  const bag::StampSource source = bag::StampSourceFromName(stamp);
  bag_->Select({{topic, {bag::kPointCloud2}}}, source);
  for (const bag::TopicInfo& t : bag_->info().topics)
    if (t.topic == topic) bag_messages_ = t.messages;
}

std::size_t LidarInput::size() const { return seq_ ? seq_->size() : bag_messages_; }

bool LidarInput::Read(std::size_t i, LidarScan* scan, std::string* error, double* stamp) {
  if (seq_) {
    const bool ok = seq_->Read(i, scan, error);
    *stamp = i < seq_->times().size() ? seq_->times()[i] : 0.1 * static_cast<double>(i);
    if (ok && i >= seq_->times().size() && scan->timestamp != 0.0) *stamp = scan->timestamp;
    return ok;
  }
  bag::MessageRef m;
  *stamp = 0.1 * static_cast<double>(i);
  if (!bag_->Next(&m)) {
    *error = bag_->path() + ": topic " + topic_ + ": no readable message left (" +
             std::to_string(bag_->stats().unreadable) + " unreadable)";
    return false;
  }
  *stamp = m.stamp_s;
  return bag_->ReadScan(scan, error);
}

const std::optional<SE3d>& LidarInput::T_cam0_velo() const {
  return seq_ ? seq_->T_cam0_velo() : no_calib_;
}

std::string LidarInput::description() const {
  if (seq_) return seq_->description();
  return "bag " + bag_->path() + ", topic " + topic_ + ", " + std::to_string(bag_messages_) +
         " PointCloud2 messages";
}

std::string LidarInput::missing_calib() const {
  if (!seq_) return "a bag carries no calib.txt (velodyne to cam0)";
  return seq_->has_calib() ? (std::filesystem::path(seq_->root()) / "calib.txt").string() +
                                 " has no Tr (velodyne to cam0) entry"
                           : std::string("no calib.txt");
}

std::string LidarInput::bag_summary() const {
  if (!bag_) return "";
  const bag::StreamStats& s = bag_->stats();
  std::string out;
  if (s.unreadable > 0) out += std::to_string(s.unreadable) + " unreadable messages skipped";
  if (s.out_of_order > 0)
    out += (out.empty() ? "" : ", ") + std::to_string(s.out_of_order) +
           " messages with a stamp older than the previous one";
  for (const std::string& w : bag_->warnings()) out += "\n  " + w;
  return out;
}

}  // namespace app
}  // namespace plucker
