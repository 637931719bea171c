#include "bag_sensor_input.h"

#include <opencv2/imgcodecs.hpp>

#include <cstring>
#include <limits>
#include <map>

namespace plucker {
namespace app {
namespace {

constexpr std::size_t kMaxWarnings = 100;

}  // namespace

CLI::Option* AddBagFlags(CLI::App* cmd, BagFlags* flags, bool imu, const std::string& bag_help) {
  CLI::Option* bag = cmd->add_option("--bag", flags->bag, bag_help);
  cmd->add_option("--image-topic", flags->image_topic,
                  "Image topic of --bag (sensor_msgs/Image mono8/bgr8/rgb8 or CompressedImage)");
  if (imu) cmd->add_option("--imu-topic", flags->imu_topic, "sensor_msgs/Imu topic of --bag");
  cmd->add_option("--stamp", flags->stamp,
                  "Time of the --bag messages: header (header.stamp) or receive (record time)")
      ->check(CLI::IsMember({"header", "receive"}))
      ->capture_default_str();
  return bag;
}

struct BagSensorStream::Impl {
  std::string path, image_topic, imu_topic;
  bag::StampSource stamp = bag::StampSource::kHeader;
  std::unique_ptr<bag::BagReader> reader;
  std::size_t image_messages = 0, dropped = 0;
  std::map<std::string, std::int64_t> last_ns;  // per topic
  std::vector<std::string> warnings;

  void Select() {
    std::vector<bag::TopicRequest> topics;
    if (!imu_topic.empty()) topics.push_back({imu_topic, {bag::kImu}});
    topics.push_back({image_topic, {bag::kImage, bag::kCompressedImage}});
    reader->Select(topics, stamp);  // ties: the IMU first
    last_ns.clear();
  }
  void Drop(const std::string& w) {
    ++dropped;
    if (warnings.size() < kMaxWarnings) warnings.push_back(w);
  }
  // The image of the current message, or the problem.
  void ReadImage(const bag::MessageRef& m, BagItem* item) const {
    std::string error;
    if (m.type == bag::kImage) {
      bag::GrayImage gray;
      if (!reader->ReadImage(&gray, &error)) {
        item->problem = error;
        return;
      }
      item->image.create(gray.height, gray.width, CV_8UC1);
      std::memcpy(item->image.data, gray.pixels.data(), gray.pixels.size());
      return;
    }
    std::string format;
    std::vector<std::uint8_t> bytes;
    if (!reader->ReadCompressed(&format, &bytes, &error)) {
      item->problem = error;
      return;
    }
    if (!bytes.empty()) item->image = cv::imdecode(bytes, cv::IMREAD_GRAYSCALE);
    if (item->image.empty())
      item->problem =
          item->name + ": the compressed image (format '" + format + "') does not decode";
  }
};

BagSensorStream::BagSensorStream(const std::string& path, const std::string& image_topic,
                                 const std::string& imu_topic, const std::string& stamp)
    : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  d.path = path, d.image_topic = image_topic, d.imu_topic = imu_topic;
  d.stamp = bag::StampSourceFromName(stamp);
  d.reader = std::make_unique<bag::BagReader>(path);
  d.Select();
  for (const bag::TopicInfo& t : d.reader->info().topics)
    if (t.topic == image_topic) d.image_messages = t.messages;
}

BagSensorStream::~BagSensorStream() = default;

std::optional<std::int64_t> BagSensorStream::FirstStampNs(const std::string& topic) {
  Impl& d = *impl_;
  const bool imu = topic == d.imu_topic;
  d.reader->Select({{topic, imu ? std::vector<std::string>{bag::kImu}
                                : std::vector<std::string>{bag::kImage, bag::kCompressedImage}}},
                   d.stamp);
  bag::MessageRef m;
  std::optional<std::int64_t> first;
  if (d.reader->Next(&m)) first = m.stamp_ns;
  d.Select();  // the stream starts again
  return first;
}

bool BagSensorStream::Next(BagItem* item) {
  Impl& d = *impl_;
  bag::MessageRef m;
  while (d.reader->Next(&m)) {
    *item = BagItem();
    item->is_imu = m.type == bag::kImu;
    item->stamp_ns = m.stamp_ns;
    item->name = d.path + ": topic " + m.topic + ", message " + std::to_string(m.index);
    const auto last = d.last_ns.find(m.topic);
    if (last != d.last_ns.end() && m.stamp_ns <= last->second) {
      d.Drop(item->name + ": stamp " + std::to_string(m.stamp_ns) +
             " ns does not increase (previous " + std::to_string(last->second) + " ns): dropped");
      continue;
    }
    if (item->is_imu) {
      std::string error;
      if (!d.reader->ReadImu(&item->imu, &error)) {
        d.Drop(error + ": dropped");
        continue;
      }
    } else {
      d.ReadImage(m, item);
    }
    d.last_ns[m.topic] = m.stamp_ns;
    return true;
  }
  return false;
}

const std::string& BagSensorStream::path() const { return impl_->path; }
std::size_t BagSensorStream::image_messages() const { return impl_->image_messages; }
std::size_t BagSensorStream::dropped() const {
  return impl_->dropped + impl_->reader->stats().unreadable;
}

std::vector<std::string> BagSensorStream::warnings() const {
  std::vector<std::string> w = impl_->reader->warnings();
  w.insert(w.end(), impl_->warnings.begin(), impl_->warnings.end());
  return w;
}

}  // namespace app
}  // namespace plucker
