#include "plucker/bag/ros2_messages_internal.h"

#include <gtest/gtest.h>

#include "plucker/bag/cdr.h"

namespace plucker {
namespace bag {
namespace {

std_msgs::Header Header(const std::string& frame_id) {
  std_msgs::Header h;
  h.stamp.sec = 1403636579, h.stamp.nsec = 763555584;
  h.frame_id = frame_id;
  return h;
}

// Decoding every prefix of a payload fails with CdrError (a named problem), never reads past it.
template <typename M>
void ExpectEveryCutFails(const std::vector<std::uint8_t>& bytes) {
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    M m;
    EXPECT_THROW(ros2::Decode(bytes.data(), n, &m), CdrError) << n << " of " << bytes.size();
  }
}

TEST(Ros2Messages, TypeNames) {
  EXPECT_EQ(ros2::Ros1Type("sensor_msgs/msg/Imu"), "sensor_msgs/Imu");
  EXPECT_EQ(ros2::Ros2Type("sensor_msgs/PointCloud2"), "sensor_msgs/msg/PointCloud2");
  EXPECT_EQ(ros2::Ros1Type("std_msgs/String"), "std_msgs/String");
  EXPECT_EQ(ros2::Ros2Type("sensor_msgs/msg/Imu"), "sensor_msgs/msg/Imu");
}

// The Imu layout by hand: stamp (8 bytes), frame_id "cam" (4 + 4 bytes: offset 16), then the
// float64 fields from offset 16; with frame_id "imu0" (4 + 5 = 9 bytes) they start at 24.
TEST(Ros2Messages, ImuLayoutByHandWithOddFrameIds) {
  for (const std::string& frame : {std::string("cam"), std::string("imu0"), std::string("")}) {
    sensor_msgs::Imu m;
    m.header = Header(frame);
    m.angular_velocity.x = 0.25, m.angular_velocity.z = -1.5;
    m.linear_acceleration.y = 9.81;
    m.orientation.w = 1.0;
    m.orientation_covariance[0] = -1.0;
    const std::vector<std::uint8_t> b = ros2::Encode(m);
    const std::size_t strings_end = 8 + 4 + frame.size() + 1;
    const std::size_t doubles = (strings_end + 7) / 8 * 8;
    ASSERT_EQ(b.size(), 4 + doubles + 8 * (4 + 9 + 3 + 9 + 3 + 9));
    double w = 0, gz = 0;
    std::memcpy(&w, b.data() + 4 + doubles + 24, 8);
    std::memcpy(&gz, b.data() + 4 + doubles + 8 * (4 + 9 + 2), 8);
    EXPECT_EQ(w, 1.0);
    EXPECT_EQ(gz, -1.5);
    sensor_msgs::Imu d;
    ros2::Decode(b.data(), b.size(), &d);
    EXPECT_EQ(d.header.stamp, m.header.stamp);
    EXPECT_EQ(d.header.frame_id, frame);
    EXPECT_EQ(d.angular_velocity.x, 0.25);
    EXPECT_EQ(d.angular_velocity.z, -1.5);
    EXPECT_EQ(d.linear_acceleration.y, 9.81);
    EXPECT_EQ(d.orientation_covariance[0], -1.0);
    ExpectEveryCutFails<sensor_msgs::Imu>(b);
  }
}

TEST(Ros2Messages, ImageAndCompressedImageRoundTrip) {
  sensor_msgs::Image m;
  m.header = Header("cam0_x");  // 7 bytes with the NUL: height at offset 20
  m.height = 2, m.width = 3, m.encoding = "mono8", m.step = 3;
  m.data = {1, 2, 3, 4, 5, 6};
  const std::vector<std::uint8_t> b = ros2::Encode(m);
  std::uint32_t height = 0;
  std::memcpy(&height, b.data() + 4 + 20, 4);
  EXPECT_EQ(height, 2u);
  sensor_msgs::Image d;
  ros2::Decode(b.data(), b.size(), &d);
  EXPECT_EQ(d.width, 3u);
  EXPECT_EQ(d.encoding, "mono8");
  EXPECT_EQ(d.step, 3u);
  EXPECT_EQ(d.data, m.data);
  ExpectEveryCutFails<sensor_msgs::Image>(b);

  sensor_msgs::CompressedImage c;
  c.header = Header("c");
  c.format = "jpeg";
  c.data = {0xff, 0xd8, 0xff};
  const std::vector<std::uint8_t> cb = ros2::Encode(c);
  sensor_msgs::CompressedImage cd;
  ros2::Decode(cb.data(), cb.size(), &cd);
  EXPECT_EQ(cd.format, "jpeg");
  EXPECT_EQ(cd.data, c.data);
  ExpectEveryCutFails<sensor_msgs::CompressedImage>(cb);
}

TEST(Ros2Messages, PointCloud2RoundTripWithOddFieldNames) {
  sensor_msgs::PointCloud2 m;
  m.header = Header("velodyne");
  m.height = 1, m.width = 2, m.point_step = 13, m.row_step = 26, m.is_dense = 1;
  for (const char* name : {"x", "y", "z", "t"}) {
    sensor_msgs::PointField f;
    f.name = name, f.offset = static_cast<std::uint32_t>(4 * m.fields.size());
    f.datatype = name[0] == 't' ? 6 : 7, f.count = 1;
    m.fields.push_back(f);
  }
  m.fields.back().name = "ring";  // 5 bytes: the next offset is not 4-aligned without padding
  m.data.assign(26, 0x5a);
  const std::vector<std::uint8_t> b = ros2::Encode(m);
  sensor_msgs::PointCloud2 d;
  ros2::Decode(b.data(), b.size(), &d);
  ASSERT_EQ(d.fields.size(), 4u);
  EXPECT_EQ(d.fields[3].name, "ring");
  EXPECT_EQ(d.fields[3].offset, 12u);
  EXPECT_EQ(d.fields[2].datatype, 7);
  EXPECT_EQ(d.point_step, 13u);
  EXPECT_EQ(d.row_step, 26u);
  EXPECT_EQ(d.data, m.data);
  EXPECT_EQ(d.is_dense, 1);
  ExpectEveryCutFails<sensor_msgs::PointCloud2>(b);
}

TEST(Ros2Messages, BigEndianAndNegativeStampsAreNamed) {
  sensor_msgs::Imu m;
  std::vector<std::uint8_t> b = ros2::Encode(m);
  b[1] = 0x00;
  try {
    ros2::Decode(b.data(), b.size(), &m);
    FAIL();
  } catch (const CdrError& e) {
    EXPECT_NE(std::string(e.what()).find("big-endian"), std::string::npos) << e.what();
  }
  b[1] = 0x01;
  b[4] = b[5] = b[6] = b[7] = 0xff;  // sec = -1
  EXPECT_THROW(ros2::Decode(b.data(), b.size(), &m), CdrError);
}

}  // namespace
}  // namespace bag
}  // namespace plucker
