#include "plucker/bag/bag_reader.h"

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>

#include "plucker/bag/cdr.h"
#include "plucker/bag/db3_internal.h"
#include "plucker/bag/point_cloud.h"
#include "plucker/bag/ros2_messages_internal.h"

namespace plucker {
namespace bag {
namespace {

constexpr std::size_t kMaxWarnings = 100;

// Reads the "#ROSBAG V2.0" file header record to tell an unindexed or truncated bag from other
// problems before rosbag_storage sees it. Returns the version (200), 0 for other versions.
int CheckFileHeader(const std::string& path, std::uint64_t file_bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw BagError(path + ": cannot open: " + std::strerror(errno));
  std::string head(4096 + 64, '\0');
  in.read(&head[0], static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  const std::string magic = "#ROSBAG V2.0\n";
  if (head.compare(0, 8, "#ROSBAG ") != 0) {
    std::string hint = "";
    if (head.compare(1, 4, "MCAP") == 0)
      hint = " (a ROS 2 MCAP bag: only ROS 1 .bag and ROS 2 .db3 are read, see docs/bags.md)";
    throw BagError(path + ": not a ROS 1 bag (no #ROSBAG header) nor a ROS 2 .db3" + hint);
  }
  if (head.compare(0, magic.size(), magic) != 0) return 0;  // V1.2: left to rosbag_storage
  // Record: int32 header length, fields "int32 length, name=value", int32 data length, data.
  auto u32 = [&head](std::size_t at) {
    std::uint32_t v = 0;
    if (at + 4 <= head.size()) std::memcpy(&v, head.data() + at, 4);
    return v;
  };
  const std::size_t begin = magic.size() + 4;
  const std::size_t end = std::min<std::size_t>(begin + u32(magic.size()), head.size());
  if (head.size() < begin) throw BagError(path + ": truncated: no file header record");
  std::uint64_t index_pos = std::numeric_limits<std::uint64_t>::max();
  for (std::size_t at = begin; at + 4 <= end;) {
    const std::uint32_t len = u32(at);
    const std::string field = head.substr(at + 4, std::min<std::size_t>(len, end - at - 4));
    if (field.compare(0, 10, "index_pos=") == 0 && field.size() == 18)
      std::memcpy(&index_pos, field.data() + 10, 8);
    at += 4 + static_cast<std::size_t>(len);
  }
  const std::string reindex = "; `rosbag reindex " + path +
                              "` (ROS 1's rosbag tool, Debian package python3-rosbag) rebuilds "
                              "the index of the messages it holds";
  if (index_pos == 0)
    throw BagError(path + ": unindexed bag (the recorder did not close it)" + reindex);
  if (index_pos == std::numeric_limits<std::uint64_t>::max())
    throw BagError(path + ": truncated or corrupt: no index_pos in the file header record");
  if (index_pos >= file_bytes)
    throw BagError(path + ": truncated: its index starts at byte " + std::to_string(index_pos) +
                   " but the file has " + std::to_string(file_bytes) + " bytes" + reindex);
  return 200;
}

std::string Join(const std::vector<std::string>& v, const char* sep) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : sep) + x;
  return s;
}

// Seconds of a ROS time, correctly rounded (ros::Time::toSec multiplies by 1e-9, which does not
// give back the decimal a folder's times.txt holds): below 2^53 ns the quotient is exact / 1e9.
double ToSeconds(const ros::Time& t) {
  if (t.sec < 9000000u) return (static_cast<double>(t.sec) * 1e9 + t.nsec) / 1e9;
  return static_cast<double>(t.sec) + t.nsec / 1e9;
}

ros::Time FromNanoseconds(std::int64_t ns) {
  ros::Time t;
  t.sec = static_cast<std::uint32_t>(ns / 1000000000);
  t.nsec = static_cast<std::uint32_t>(ns % 1000000000);
  return t;
}

// A rosbag2 folder, or a file that starts as SQLite does.
bool IsDb3(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return true;
  std::ifstream in(path, std::ios::binary);
  char head[16] = {};
  in.read(head, sizeof(head));
  return in.gcount() == 16 && std::memcmp(head, "SQLite format 3", 16) == 0;
}

std::int64_t ToNanoseconds(const ros::Time& t) {
  return static_cast<std::int64_t>(t.sec) * 1000000000 + static_cast<std::int64_t>(t.nsec);
}

// One selected topic: its view and the message it is at (decoded, one of the pointers set).
struct TopicStream {
  std::string topic, type;
  std::unique_ptr<rosbag::View> view;
  rosbag::View::iterator it;
  std::unique_ptr<Db3Cursor> cursor;  // a .db3 bag: instead of the view
  std::size_t index = 0;
  bool valid = false;
  double receive_s = 0.0, header_s = 0.0, last_stamp = -std::numeric_limits<double>::infinity();
  std::int64_t receive_ns = 0, header_ns = 0;
  sensor_msgs::PointCloud2::ConstPtr cloud;
  sensor_msgs::Imu::ConstPtr imu;
  sensor_msgs::Image::ConstPtr image;
  sensor_msgs::CompressedImage::ConstPtr compressed;
};

}  // namespace

StampSource StampSourceFromName(const std::string& name) {
  if (name == "header") return StampSource::kHeader;
  if (name == "receive") return StampSource::kReceive;
  throw BagError("--stamp must be header or receive, got '" + name + "'");
}

struct BagReader::Impl {
  std::string path;
  rosbag::Bag bag;
  std::unique_ptr<Db3File> db3;  // set for a ROS 2 bag (.db3 or a rosbag2 folder)
  BagInfo info;
  StampSource stamp = StampSource::kHeader;
  std::vector<std::unique_ptr<TopicStream>> streams;
  TopicStream current;  // the message Next moved to (its pointers)
  StreamStats stats;
  std::vector<std::string> warnings;

  std::string Where(const TopicStream& s) const {
    return path + ": topic " + s.topic + ", message " + std::to_string(s.index);
  }

  // Decodes the message at s.it, skipping (and counting) unreadable ones; s.valid = false at end.
  void Load(TopicStream* s) {
    s->valid = false;
    if (s->cursor) {
      LoadDb3(s);
      return;
    }
    for (; s->it != s->view->end(); ++s->it, ++s->index) {
      try {
        const rosbag::MessageInstance& m = *s->it;
        s->receive_s = ToSeconds(m.getTime());
        s->receive_ns = ToNanoseconds(m.getTime());
        s->cloud.reset(), s->imu.reset(), s->image.reset(), s->compressed.reset();
        const std_msgs::Header* header = nullptr;
        if (s->type == kPointCloud2 && (s->cloud = m.instantiate<sensor_msgs::PointCloud2>()))
          header = &s->cloud->header;
        else if (s->type == kImu && (s->imu = m.instantiate<sensor_msgs::Imu>()))
          header = &s->imu->header;
        else if (s->type == kImage && (s->image = m.instantiate<sensor_msgs::Image>()))
          header = &s->image->header;
        else if (s->type == kCompressedImage &&
                 (s->compressed = m.instantiate<sensor_msgs::CompressedImage>()))
          header = &s->compressed->header;
        if (!header) {
          Warn(Where(*s) + ": cannot deserialise as " + s->type + " (its definition differs: md5 " +
               m.getMD5Sum() + ")");
          continue;
        }
        s->header_s = ToSeconds(header->stamp);
        s->header_ns = ToNanoseconds(header->stamp);
        s->valid = true;
        return;
      } catch (const std::exception& e) {
        Warn(Where(*s) + ": unreadable: " + e.what());
      }
    }
  }

  template <typename T>
  bool DecodeCdr(const std::uint8_t* data, std::size_t size, TopicStream* s,
                 boost::shared_ptr<const T>* out) {
    auto m = boost::make_shared<T>();
    try {
      ros2::Decode(data, size, m.get());
    } catch (const CdrError& e) {
      Warn(Where(*s) + ": cannot deserialise as " + ros2::Ros2Type(s->type) + ": " + e.what());
      return false;
    }
    s->header_s = ToSeconds(m->header.stamp);
    s->header_ns = ToNanoseconds(m->header.stamp);
    *out = m;
    return true;
  }

  void LoadDb3(TopicStream* s) {
    std::int64_t ns = 0;
    const std::uint8_t* data = nullptr;
    std::size_t size = 0;
    for (; s->cursor->Next(&ns, &data, &size); ++s->index) {
      s->cloud.reset(), s->imu.reset(), s->image.reset(), s->compressed.reset();
      if (ns < 0) {
        Warn(Where(*s) + ": negative receive timestamp " + std::to_string(ns));
        continue;
      }
      s->receive_s = ToSeconds(FromNanoseconds(ns));
      s->receive_ns = ns;
      if ((s->type == kPointCloud2 && DecodeCdr(data, size, s, &s->cloud)) ||
          (s->type == kImu && DecodeCdr(data, size, s, &s->imu)) ||
          (s->type == kImage && DecodeCdr(data, size, s, &s->image)) ||
          (s->type == kCompressedImage && DecodeCdr(data, size, s, &s->compressed))) {
        s->valid = true;
        return;
      }
    }
  }

  void OpenDb3() {
    const std::string file = ResolveDb3(path);
    db3 = std::make_unique<Db3File>(file);
    std::error_code ec;
    info.bytes = std::filesystem::file_size(file, ec);
    info.format = "rosbag2 SQLite3 (.db3)";
    for (const Db3Topic& t : db3->topics()) {
      TopicInfo i;
      i.topic = t.name, i.type = t.type, i.messages = t.messages;
      i.first_s = ToSeconds(FromNanoseconds(std::max<std::int64_t>(t.first_ns, 0)));
      i.last_s = ToSeconds(FromNanoseconds(std::max<std::int64_t>(t.last_ns, 0)));
      if (i.messages > 0) {
        info.start_s = info.messages == 0 ? i.first_s : std::min(info.start_s, i.first_s);
        info.end_s = info.messages == 0 ? i.last_s : std::max(info.end_s, i.last_s);
      }
      info.messages += t.messages;
      info.topics.push_back(i);
    }
  }

  void Warn(const std::string& w) {
    ++stats.unreadable;
    if (warnings.size() < kMaxWarnings) warnings.push_back(w);
  }

  double Stamp(const TopicStream& s) const {
    return stamp == StampSource::kHeader ? s.header_s : s.receive_s;
  }

  bool Check(const char* type, std::string* error) const {
    if (!current.valid) {
      if (error) *error = path + ": no current message";
      return false;
    }
    if (current.type == type) return true;
    if (error) *error = Where(current) + ": is " + current.type + ", not " + type;
    return false;
  }
};

BagReader::BagReader(const std::string& path) : impl_(new Impl) {
  Impl& d = *impl_;
  d.path = path;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw BagError(path + ": no such file");
  d.info.path = path;
  if (IsDb3(path)) {
    d.OpenDb3();
    return;
  }
  if (!std::filesystem::is_regular_file(path, ec)) throw BagError(path + ": not a file");
  d.info.bytes = std::filesystem::file_size(path, ec);
  d.info.version = CheckFileHeader(path, d.info.bytes);
  try {
    d.bag.open(path, rosbag::bagmode::Read);
    rosbag::View all(d.bag);
    std::map<std::string, TopicInfo> topics;
    for (const rosbag::ConnectionInfo* c : all.getConnections()) {
      TopicInfo& t = topics[c->topic];
      t.topic = c->topic;
      if (t.type.empty())
        t.type = c->datatype;
      else if (t.type.find(c->datatype) == std::string::npos)
        t.type += " | " + c->datatype;
    }
    for (auto& [name, t] : topics) {
      rosbag::View v(d.bag, rosbag::TopicQuery(name));
      t.messages = v.size();
      if (t.messages > 0)
        t.first_s = ToSeconds(v.getBeginTime()), t.last_s = ToSeconds(v.getEndTime());
      d.info.topics.push_back(t);
    }
    d.info.messages = all.size();
    if (d.info.messages > 0)
      d.info.start_s = ToSeconds(all.getBeginTime()), d.info.end_s = ToSeconds(all.getEndTime());
  } catch (const std::exception& e) {  // rosbag::BagException and others
    throw BagError(path + ": cannot read the bag: " + e.what());
  }
}

BagReader::~BagReader() = default;

const BagInfo& BagReader::info() const { return impl_->info; }
const std::string& BagReader::path() const { return impl_->path; }

void BagReader::Select(const std::vector<TopicRequest>& requests, StampSource stamp) {
  Impl& d = *impl_;
  d.streams.clear();
  d.current = TopicStream();
  d.stats = StreamStats();
  d.warnings.clear();
  d.stamp = stamp;
  for (const TopicRequest& r : requests) {
    const auto t = std::find_if(d.info.topics.begin(), d.info.topics.end(),
                                [&r](const TopicInfo& i) { return i.topic == r.topic; });
    if (t == d.info.topics.end()) {
      std::vector<std::string> have;
      for (const TopicInfo& i : d.info.topics) have.push_back(i.topic + " (" + i.type + ")");
      throw BagError(d.path + ": no topic " + r.topic +
                     "; the bag has: " + (have.empty() ? "no topics" : Join(have, ", ")));
    }
    const std::string type = ros2::Ros1Type(t->type);  // a .db3 names "sensor_msgs/msg/Imu"
    if (std::find(r.types.begin(), r.types.end(), type) == r.types.end())
      throw BagError(d.path + ": topic " + r.topic + " has type " + t->type + ", expected " +
                     Join(r.types, " or "));
    auto s = std::make_unique<TopicStream>();
    s->topic = r.topic;
    s->type = type;
    if (d.db3) {
      const Db3Topic& db = *std::find_if(d.db3->topics().begin(), d.db3->topics().end(),
                                         [&r](const Db3Topic& i) { return i.name == r.topic; });
      if (db.format != "cdr")
        throw BagError(d.path + ": topic " + r.topic + " is serialised as '" + db.format +
                       "', only cdr is read");
      s->cursor = d.db3->Open(db.id);
      d.Load(s.get());
      d.streams.push_back(std::move(s));
      continue;
    }
    try {
      s->view = std::make_unique<rosbag::View>(d.bag, rosbag::TopicQuery(r.topic));
      s->it = s->view->begin();
    } catch (const std::exception& e) {
      throw BagError(d.path + ": topic " + r.topic + ": cannot read: " + e.what());
    }
    d.Load(s.get());
    d.streams.push_back(std::move(s));
  }
}

bool BagReader::Next(MessageRef* message) {
  Impl& d = *impl_;
  TopicStream* best = nullptr;
  for (const auto& s : d.streams) {
    if (!s->valid) continue;
    if (!best || d.Stamp(*s) < d.Stamp(*best)) best = s.get();  // ties: request order
  }
  if (!best) {
    d.current.valid = false;
    return false;
  }
  TopicStream& c = d.current;
  c.topic = best->topic, c.type = best->type, c.index = best->index, c.valid = true;
  c.receive_s = best->receive_s, c.header_s = best->header_s;
  c.receive_ns = best->receive_ns, c.header_ns = best->header_ns;
  c.cloud = best->cloud, c.imu = best->imu, c.image = best->image, c.compressed = best->compressed;
  const double stamp = d.Stamp(*best);
  if (stamp < best->last_stamp) ++d.stats.out_of_order;
  best->last_stamp = stamp;
  ++d.stats.messages;
  if (!best->cursor) ++best->it;
  ++best->index;
  d.Load(best);
  if (message) {
    message->topic = c.topic, message->type = c.type, message->index = c.index;
    message->receive_s = c.receive_s, message->header_s = c.header_s, message->stamp_s = stamp;
    message->receive_ns = c.receive_ns, message->header_ns = c.header_ns;
    message->stamp_ns = d.stamp == StampSource::kHeader ? c.header_ns : c.receive_ns;
  }
  return true;
}

bool BagReader::ReadScan(sensor::LidarScan* scan, std::string* error) const {
  const Impl& d = *impl_;
  if (!d.Check(kPointCloud2, error)) return false;
  const sensor_msgs::PointCloud2& m = *d.current.cloud;
  CloudLayout layout;
  layout.width = m.width, layout.height = m.height;
  layout.point_step = m.point_step, layout.row_step = m.row_step;
  layout.big_endian = m.is_bigendian;
  for (const auto& f : m.fields) layout.fields.push_back({f.name, f.offset, f.datatype, f.count});
  const std::string problem = CloudToScan(layout, m.data.data(), m.data.size(), scan);
  if (!problem.empty()) {
    if (error) *error = d.Where(d.current) + ": " + problem;
    return false;
  }
  if (scan->timestamp == 0.0) scan->timestamp = ToSeconds(m.header.stamp);
  return true;
}

bool BagReader::ReadImu(sensor::ImuSample* sample, std::string* error) const {
  const Impl& d = *impl_;
  if (!d.Check(kImu, error)) return false;
  const sensor_msgs::Imu& m = *d.current.imu;
  *sample = sensor::ImuSample();
  sample->t = d.Stamp(d.current);
  sample->gyro = Eigen::Vector3d(m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z);
  sample->accel =
      Eigen::Vector3d(m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z);
  if (!sample->gyro.allFinite() || !sample->accel.allFinite()) {
    if (error) *error = d.Where(d.current) + ": non-finite angular velocity or acceleration";
    return false;
  }
  return true;
}

bool BagReader::ReadImage(GrayImage* image, std::string* error) const {
  const Impl& d = *impl_;
  if (!d.Check(kImage, error)) return false;
  const sensor_msgs::Image& m = *d.current.image;
  int channels = 0;
  int r = 0, b = 2;  // channel of red and blue
  if (m.encoding == "mono8" || m.encoding == "8UC1") {
    channels = 1;
  } else if (m.encoding == "bgr8" || m.encoding == "bgra8") {
    channels = m.encoding == "bgr8" ? 3 : 4, r = 2, b = 0;
  } else if (m.encoding == "rgb8" || m.encoding == "rgba8") {
    channels = m.encoding == "rgb8" ? 3 : 4;
  } else {
    if (error)
      *error = d.Where(d.current) + ": image encoding '" + m.encoding +
               "' is not supported (mono8, bgr8, rgb8, bgra8, rgba8)";
    return false;
  }
  const std::size_t w = m.width, h = m.height;
  if (w == 0 || h == 0 || m.step < w * channels || m.data.size() / m.step < h) {
    if (error)
      *error = d.Where(d.current) + ": image " + std::to_string(w) + "x" + std::to_string(h) +
               " with step " + std::to_string(m.step) + " does not fit its " +
               std::to_string(m.data.size()) + " bytes";
    return false;
  }
  image->width = static_cast<int>(w), image->height = static_cast<int>(h);
  image->pixels.resize(w * h);
  for (std::size_t y = 0; y < h; ++y) {
    const std::uint8_t* row = m.data.data() + y * m.step;
    std::uint8_t* out = image->pixels.data() + y * w;
    if (channels == 1) {
      std::memcpy(out, row, w);
      continue;
    }
    for (std::size_t x = 0; x < w; ++x) {  // OpenCV's fixed-point BGR2GRAY weights
      const std::uint8_t* p = row + x * channels;
      out[x] = static_cast<std::uint8_t>((p[r] * 4899 + p[1] * 9617 + p[b] * 1868 + 8192) >> 14);
    }
  }
  return true;
}

bool BagReader::ReadCompressed(std::string* format, std::vector<std::uint8_t>* bytes,
                               std::string* error) const {
  const Impl& d = *impl_;
  if (!d.Check(kCompressedImage, error)) return false;
  *format = d.current.compressed->format;
  *bytes = d.current.compressed->data;
  return true;
}

const StreamStats& BagReader::stats() const { return impl_->stats; }
const std::vector<std::string>& BagReader::warnings() const { return impl_->warnings; }

}  // namespace bag
}  // namespace plucker
