#include "plucker/bag/bag_writer.h"

#include <rosbag/bag.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>

#include <filesystem>

#include "plucker/bag/bag_reader.h"
#include "plucker/bag/db3_internal.h"
#include "plucker/bag/ros2_messages_internal.h"

namespace plucker {
namespace bag {
namespace {

ros::Time ToTime(double t, double min_s, const std::string& what) {
  if (!(t >= min_s) || t > 4.0e9)
    throw BagError(what + " time " + std::to_string(t) + " s out of range");
  ros::Time time;
  time.fromSec(t);
  if (time < ros::TIME_MIN && min_s > 0.0) time = ros::TIME_MIN;
  return time;
}

ros::Time NsToTime(std::int64_t ns, std::int64_t min_ns, const std::string& what) {
  if (ns < min_ns || ns > 4000000000LL * 1000000000LL)
    throw BagError(what + " time " + std::to_string(ns) + " ns out of range");
  ros::Time time;
  time.sec = static_cast<std::uint32_t>(ns / 1000000000);
  time.nsec = static_cast<std::uint32_t>(ns % 1000000000);
  return time;
}

sensor_msgs::Imu ImuMessage(const std_msgs::Header& header, const sensor::ImuSample& sample) {
  sensor_msgs::Imu m;
  m.header = header;
  m.orientation_covariance[0] = -1.0;  // no orientation (REP 145)
  m.angular_velocity.x = sample.gyro.x(), m.angular_velocity.y = sample.gyro.y();
  m.angular_velocity.z = sample.gyro.z();
  m.linear_acceleration.x = sample.accel.x(), m.linear_acceleration.y = sample.accel.y();
  m.linear_acceleration.z = sample.accel.z();
  return m;
}

sensor_msgs::Image ImageMessage(const std_msgs::Header& header, int width, int height,
                                const std::string& encoding,
                                const std::vector<std::uint8_t>& data) {
  sensor_msgs::Image m;
  m.header = header;
  m.width = static_cast<std::uint32_t>(width), m.height = static_cast<std::uint32_t>(height);
  m.encoding = encoding;
  m.step = height > 0 ? static_cast<std::uint32_t>(data.size() / height) : 0;
  m.data = data;
  return m;
}

}  // namespace

bool IsDb3Path(const std::string& path) {
  return path.size() >= 4 && path.compare(path.size() - 4, 4, ".db3") == 0;
}

struct BagWriter::Impl {
  std::string path;
  BagWriterOptions options;
  rosbag::Bag bag;
  std::unique_ptr<Db3Writer> db3;  // a path ending in .db3: a ROS 2 bag
  bool open = false;

  std_msgs::Header Header(double header_s) const {
    return HeaderAt(ToTime(header_s, 0.0, path + ": header"));
  }
  std_msgs::Header HeaderAt(const ros::Time& stamp) const {
    std_msgs::Header h;
    h.stamp = stamp;
    h.frame_id = options.frame_id;
    return h;
  }
  template <typename T>
  void Write(const std::string& topic, double receive_s, const T& msg) {
    WriteAt(topic, ToTime(receive_s, 1e-9, path + ": receive"), msg);
  }
  template <typename T>
  void WriteAt(const std::string& topic, const ros::Time& receive, const T& msg) {
    if (!open) throw BagError(path + ": written after Close");
    if (db3) {
      const std::int64_t ns = static_cast<std::int64_t>(receive.sec) * 1000000000 +
                              static_cast<std::int64_t>(receive.nsec);
      return db3->Write(topic, ros2::Ros2Type(ros::message_traits::DataType<T>::value()), ns,
                        ros2::Encode(msg));
    }
    try {
      bag.write(topic, receive, msg);
    } catch (const rosbag::BagException& e) {
      throw BagError(path + ": write failed: " + e.what());
    }
  }
};

BagWriter::BagWriter(const std::string& path, const BagWriterOptions& options) : impl_(new Impl) {
  options.Check();
  impl_->path = path;
  impl_->options = options;
  std::error_code ec;
  if (std::filesystem::exists(path, ec))
    throw BagError(path + ": exists; refusing to overwrite it");
  if (IsDb3Path(path)) {
    if (options.lz4) throw BagError(path + ": --lz4 is for ROS 1 bags, not .db3");
    impl_->db3 = std::make_unique<Db3Writer>(path);
    impl_->open = true;
    return;
  }
  try {
    impl_->bag.open(path, rosbag::bagmode::Write);
    if (options.lz4) impl_->bag.setCompression(rosbag::compression::LZ4);
  } catch (const rosbag::BagException& e) {
    throw BagError(path + ": cannot create: " + e.what());
  }
  impl_->open = true;
}

BagWriter::~BagWriter() {
  try {
    Close();
  } catch (...) {  // a destructor does not throw; Close() reports it to callers that ask
  }
}

void BagWriter::Close() {
  if (!impl_->open) return;
  impl_->open = false;
  if (impl_->db3) {
    impl_->db3->Close();
    return;
  }
  try {
    impl_->bag.close();
  } catch (const rosbag::BagException& e) {
    throw BagError(impl_->path + ": close failed: " + e.what());
  }
}

void BagWriter::WriteScan(const std::string& topic, double receive_s, double header_s,
                          const sensor::LidarScan& scan) {
  const CloudLayout layout = ScanLayout(scan);
  std::vector<std::uint8_t> data;
  ScanToCloudData(scan, layout, &data);
  WriteCloud(topic, receive_s, header_s, layout, data);
}

void BagWriter::WriteCloud(const std::string& topic, double receive_s, double header_s,
                           const CloudLayout& layout, const std::vector<std::uint8_t>& data) {
  sensor_msgs::PointCloud2 m;
  m.header = impl_->Header(header_s);
  m.width = layout.width, m.height = layout.height;
  m.point_step = layout.point_step, m.row_step = layout.row_step;
  m.is_bigendian = layout.big_endian;
  m.is_dense = false;
  for (const CloudField& f : layout.fields) {
    sensor_msgs::PointField p;
    p.name = f.name, p.offset = f.offset, p.datatype = f.datatype, p.count = f.count;
    m.fields.push_back(p);
  }
  m.data = data;
  impl_->Write(topic, receive_s, m);
}

void BagWriter::WriteImu(const std::string& topic, double receive_s,
                         const sensor::ImuSample& sample) {
  impl_->Write(topic, receive_s, ImuMessage(impl_->Header(sample.t), sample));
}

void BagWriter::WriteImuNs(const std::string& topic, std::int64_t receive_ns,
                           std::int64_t header_ns, const sensor::ImuSample& sample) {
  const std::string& p = impl_->path;
  impl_->WriteAt(topic, NsToTime(receive_ns, 1, p + ": receive"),
                 ImuMessage(impl_->HeaderAt(NsToTime(header_ns, 0, p + ": header")), sample));
}

void BagWriter::WriteImageNs(const std::string& topic, std::int64_t receive_ns,
                             std::int64_t header_ns, int width, int height,
                             const std::string& encoding, const std::vector<std::uint8_t>& data) {
  const std::string& p = impl_->path;
  impl_->WriteAt(topic, NsToTime(receive_ns, 1, p + ": receive"),
                 ImageMessage(impl_->HeaderAt(NsToTime(header_ns, 0, p + ": header")), width,
                              height, encoding, data));
}

void BagWriter::WriteImage(const std::string& topic, double receive_s, double header_s, int width,
                           int height, const std::string& encoding,
                           const std::vector<std::uint8_t>& data) {
  impl_->Write(topic, receive_s,
               ImageMessage(impl_->Header(header_s), width, height, encoding, data));
}

void BagWriter::WriteCompressedNs(const std::string& topic, std::int64_t receive_ns,
                                  std::int64_t header_ns, const std::string& format,
                                  const std::vector<std::uint8_t>& data) {
  const std::string& p = impl_->path;
  sensor_msgs::CompressedImage m;
  m.header = impl_->HeaderAt(NsToTime(header_ns, 0, p + ": header"));
  m.format = format;
  m.data = data;
  impl_->WriteAt(topic, NsToTime(receive_ns, 1, p + ": receive"), m);
}

void BagWriter::WriteCompressed(const std::string& topic, double receive_s, double header_s,
                                const std::string& format, const std::vector<std::uint8_t>& data) {
  sensor_msgs::CompressedImage m;
  m.header = impl_->Header(header_s);
  m.format = format;
  m.data = data;
  impl_->Write(topic, receive_s, m);
}

}  // namespace bag
}  // namespace plucker
