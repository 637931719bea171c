#include "plucker/bag/bag_reader.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "plucker/bag/bag_test_utils.h"
#include "plucker/bag/bag_writer.h"
#include "plucker/io/io_test_utils.h"

namespace plucker {
namespace bag {
namespace {

using io::testing::ScratchDir;
using testing::ErrorOf;
using testing::Scan;

// Scans at 10 Hz on /points (receive 5 ms after the header stamp), IMU at 100 Hz on /imu whose
// receive times lag by 50 ms: receive order and header order differ.
std::string WriteSmallBag(const ScratchDir& dir) {
  const std::string path = (dir / "small.bag").string();
  BagWriter w(path);
  for (int k = 0; k < 3; ++k) w.WriteScan("/points", 1.005 + 0.1 * k, 1.0 + 0.1 * k, Scan(k));
  for (int k = 0; k < 30; ++k) {
    sensor::ImuSample s;
    s.t = 1.0 + 0.01 * k;
    s.gyro = Eigen::Vector3d(0.1 * k, 0, 0);
    s.accel = Eigen::Vector3d(0, 0, 9.81);
    w.WriteImu("/imu", s.t + 0.05, s);
  }
  w.Close();
  return path;
}

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}
void WriteAll(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

TEST(BagReader, InfoListsTopicsTypesCountsAndSpans) {
  ScratchDir dir;
  const BagReader r(WriteSmallBag(dir));
  const BagInfo& info = r.info();
  EXPECT_EQ(info.version, 200);
  EXPECT_EQ(info.messages, 33u);
  ASSERT_EQ(info.topics.size(), 2u);
  EXPECT_EQ(info.topics[0].topic, "/imu");
  EXPECT_EQ(info.topics[0].type, kImu);
  EXPECT_EQ(info.topics[0].messages, 30u);
  EXPECT_NEAR(info.topics[0].first_s, 1.05, 1e-9);
  EXPECT_NEAR(info.topics[0].last_s, 1.34, 1e-9);
  EXPECT_EQ(info.topics[1].topic, "/points");
  EXPECT_EQ(info.topics[1].type, kPointCloud2);
  EXPECT_EQ(info.topics[1].messages, 3u);
  EXPECT_NEAR(info.start_s, 1.005, 1e-9);
  EXPECT_NEAR(info.end_s, 1.34, 1e-9);
}

// The order of (topic, index) pairs a stream gives.
std::vector<std::string> Order(BagReader* r, StampSource stamp) {
  r->Select({{"/points", {kPointCloud2}}, {"/imu", {kImu}}}, stamp);
  std::vector<std::string> order;
  MessageRef m;
  double last = -1.0;
  while (r->Next(&m)) {
    EXPECT_GE(m.stamp_s, last);
    last = m.stamp_s;
    order.push_back(m.topic.substr(1, 1) + std::to_string(m.index));
  }
  return order;
}

TEST(BagReader, StreamsInHeaderOrReceiveOrder) {
  ScratchDir dir;
  BagReader r(WriteSmallBag(dir));
  const std::vector<std::string> header = Order(&r, StampSource::kHeader);
  ASSERT_EQ(header.size(), 33u);
  // Header: the scan at 1.0 ties with imu 0 (request order: points first), then imu 0..9.
  EXPECT_EQ(header[0], "p0");
  EXPECT_EQ(header[1], "i0");
  EXPECT_EQ(header[10], "i9");
  EXPECT_EQ(header[11], "p1");
  const std::vector<std::string> receive = Order(&r, StampSource::kReceive);
  ASSERT_EQ(receive.size(), 33u);
  // Receive: scan 0 at 1.005, scans 1 (1.105) after imu 5 (1.10).
  EXPECT_EQ(receive[0], "p0");
  EXPECT_EQ(receive[1], "i0");
  EXPECT_EQ(receive[6], "i5");
  EXPECT_EQ(receive[7], "p1");
  EXPECT_EQ(r.stats().unreadable, 0u);
  EXPECT_EQ(r.stats().out_of_order, 0u);
}

TEST(BagReader, DecodesScansAndImu) {
  ScratchDir dir;
  BagReader r(WriteSmallBag(dir));
  r.Select({{"/points", {kPointCloud2}}, {"/imu", {kImu}}});
  MessageRef m;
  std::size_t scans = 0, imus = 0;
  std::string error;
  while (r.Next(&m)) {
    if (m.topic == "/points") {
      sensor::LidarScan scan;
      ASSERT_TRUE(r.ReadScan(&scan, &error)) << error;
      const sensor::LidarScan want = Scan(static_cast<int>(m.index));
      EXPECT_EQ(scan.points, want.points);
      EXPECT_EQ(scan.intensity, want.intensity);
      EXPECT_NEAR(scan.timestamp, 1.0 + 0.1 * m.index, 1e-9);
      sensor::ImuSample s;
      EXPECT_FALSE(r.ReadImu(&s, &error));  // a scan is not an IMU sample
      EXPECT_NE(error.find("topic /points, message " + std::to_string(m.index) +
                           ": is sensor_msgs/PointCloud2, not sensor_msgs/Imu"),
                std::string::npos)
          << error;
      ++scans;
    } else {
      sensor::ImuSample s;
      ASSERT_TRUE(r.ReadImu(&s, &error)) << error;
      EXPECT_NEAR(s.t, 1.0 + 0.01 * m.index, 1e-9);
      EXPECT_NEAR(s.gyro.x(), 0.1 * m.index, 1e-12);
      EXPECT_EQ(s.accel, Eigen::Vector3d(0, 0, 9.81));
      ++imus;
    }
  }
  EXPECT_EQ(scans, 3u);
  EXPECT_EQ(imus, 30u);
}

TEST(BagReader, ImagesMonoColourAndUnsupportedEncodings) {
  ScratchDir dir;
  const std::string path = (dir / "images.bag").string();
  {
    BagWriter w(path);
    w.WriteImage("/cam", 1.0, 1.0, 2, 1, "mono8", {7, 200});
    w.WriteImage("/cam", 1.1, 1.1, 2, 1, "bgr8", {255, 0, 0, 0, 0, 255});  // blue, red
    w.WriteImage("/cam", 1.2, 1.2, 2, 1, "rgb8", {255, 0, 0, 0, 0, 255});  // red, blue
    w.WriteImage("/cam", 1.3, 1.3, 2, 1, "mono16", {0, 1, 2, 3});
    w.WriteImage("/cam", 1.4, 1.4, 4, 1, "mono8", {1, 2});  // data shorter than the image
    w.WriteCompressed("/jpg", 1.5, 1.5, "jpeg", {0xFF, 0xD8});
  }
  BagReader r(path);
  r.Select({{"/cam", {kImage}}, {"/jpg", {kCompressedImage}}});
  MessageRef m;
  GrayImage g;
  std::string error;
  ASSERT_TRUE(r.Next(&m));
  ASSERT_TRUE(r.ReadImage(&g, &error)) << error;
  EXPECT_EQ(g.pixels, (std::vector<std::uint8_t>{7, 200}));
  ASSERT_TRUE(r.Next(&m));
  ASSERT_TRUE(r.ReadImage(&g, &error)) << error;
  EXPECT_EQ(g.pixels, (std::vector<std::uint8_t>{29, 76}));  // OpenCV: blue 29, red 76
  ASSERT_TRUE(r.Next(&m));
  ASSERT_TRUE(r.ReadImage(&g, &error)) << error;
  EXPECT_EQ(g.pixels, (std::vector<std::uint8_t>{76, 29}));
  ASSERT_TRUE(r.Next(&m));
  EXPECT_FALSE(r.ReadImage(&g, &error));
  EXPECT_NE(error.find(path + ": topic /cam, message 3: image encoding 'mono16' is not supported"),
            std::string::npos)
      << error;
  ASSERT_TRUE(r.Next(&m));
  EXPECT_FALSE(r.ReadImage(&g, &error));
  EXPECT_NE(error.find("message 4: image 4x1 with step 2 does not fit"), std::string::npos)
      << error;
  ASSERT_TRUE(r.Next(&m));
  std::string format;
  std::vector<std::uint8_t> bytes;
  ASSERT_TRUE(r.ReadCompressed(&format, &bytes, &error)) << error;
  EXPECT_EQ(format, "jpeg");
  EXPECT_EQ(bytes, (std::vector<std::uint8_t>{0xFF, 0xD8}));
  EXPECT_FALSE(r.Next(&m));
}

TEST(BagReader, BadCloudsAreNamedWithTopicAndIndex) {
  ScratchDir dir;
  const std::string path = (dir / "clouds.bag").string();
  {
    BagWriter w(path);
    sensor::LidarScan s = Scan(0);
    CloudLayout layout = ScanLayout(s);
    std::vector<std::uint8_t> data;
    ScanToCloudData(s, layout, &data);
    w.WriteCloud("/c", 1.0, 1.0, layout, data);
    CloudLayout big = layout;
    big.big_endian = true;
    w.WriteCloud("/c", 1.1, 1.1, big, data);
    CloudLayout no_xyz = layout;
    no_xyz.fields.erase(no_xyz.fields.begin());
    w.WriteCloud("/c", 1.2, 1.2, no_xyz, data);
  }
  BagReader r(path);
  r.Select({{"/c", {kPointCloud2}}});
  MessageRef m;
  sensor::LidarScan scan;
  std::string error;
  ASSERT_TRUE(r.Next(&m));
  EXPECT_TRUE(r.ReadScan(&scan, &error)) << error;
  ASSERT_TRUE(r.Next(&m));
  EXPECT_FALSE(r.ReadScan(&scan, &error));
  EXPECT_EQ(error, path +
                       ": topic /c, message 1: big-endian point data is not supported "
                       "(is_bigendian = true)");
  ASSERT_TRUE(r.Next(&m));
  EXPECT_FALSE(r.ReadScan(&scan, &error));
  EXPECT_EQ(error, path + ": topic /c, message 2: no x, y, z fields (fields: y, z, intensity)");
  EXPECT_FALSE(r.Next(&m));
}

TEST(BagReader, MissingTopicListsTheTopicsAndWrongTypeIsNamed) {
  ScratchDir dir;
  const std::string path = WriteSmallBag(dir);
  BagReader r(path);
  try {
    r.Select({{"/velodyne_points", {kPointCloud2}}});
    FAIL() << "no error";
  } catch (const BagError& e) {
    EXPECT_EQ(std::string(e.what()), path +
                                         ": no topic /velodyne_points; the bag has: /imu "
                                         "(sensor_msgs/Imu), /points (sensor_msgs/PointCloud2)");
  }
  try {
    r.Select({{"/imu", {kPointCloud2}}});
    FAIL() << "no error";
  } catch (const BagError& e) {
    EXPECT_EQ(std::string(e.what()),
              path + ": topic /imu has type sensor_msgs/Imu, expected sensor_msgs/PointCloud2");
  }
  EXPECT_THROW(StampSourceFromName("arrival"), BagError);
}

TEST(BagReader, UnindexedTruncatedAndForeignFilesAreNamed) {
  ScratchDir dir;
  const std::string good = WriteSmallBag(dir);
  const std::string bytes = ReadAll(good);

  // Unindexed: as a recorder leaves it when killed (index_pos 0 in the file header record).
  std::string unindexed = bytes;
  const std::size_t at = unindexed.find("index_pos=");
  ASSERT_NE(at, std::string::npos);
  std::memset(&unindexed[at + 10], 0, 8);
  const std::string p1 = (dir / "unindexed.bag").string();
  WriteAll(p1, unindexed.substr(0, unindexed.size() / 2));
  EXPECT_NE(ErrorOf(p1).find(p1 + ": unindexed bag"), std::string::npos) << ErrorOf(p1);
  EXPECT_NE(ErrorOf(p1).find("rosbag reindex " + p1), std::string::npos) << ErrorOf(p1);

  const std::string p2 = (dir / "truncated.bag").string();
  WriteAll(p2, bytes.substr(0, bytes.size() * 2 / 3));
  EXPECT_NE(ErrorOf(p2).find(p2 + ": truncated: its index starts at byte"), std::string::npos)
      << ErrorOf(p2);

  const std::string p3 = (dir / "cut_header.bag").string();
  WriteAll(p3, bytes.substr(0, 20));
  EXPECT_NE(ErrorOf(p3).find(p3 + ": truncated"), std::string::npos) << ErrorOf(p3);

  // The index is there but the bytes after it are cut: rosbag_storage's error, named.
  const std::string p4 = (dir / "cut_index.bag").string();
  WriteAll(p4, bytes.substr(0, bytes.size() - 10));
  EXPECT_NE(ErrorOf(p4).find(p4 + ": "), std::string::npos) << ErrorOf(p4);

  const std::string p5 = (dir / "rosbag2.db3").string();
  WriteAll(p5, std::string("SQLite format 3") + std::string(100, '\0'));
  EXPECT_NE(ErrorOf(p5).find(p5 + ": not an SQLite database"), std::string::npos) << ErrorOf(p5);
  const std::string p6 = (dir / "rosbag2.mcap").string();
  WriteAll(p6, std::string("\x89MCAP0\r\n") + std::string(100, '\0'));
  EXPECT_NE(ErrorOf(p6).find("(a ROS 2 MCAP bag: only ROS 1 .bag and ROS 2 .db3 are read"),
            std::string::npos)
      << ErrorOf(p6);

  EXPECT_EQ(ErrorOf((dir / "none.bag").string()), (dir / "none.bag").string() + ": no such file");
}

// A message whose bytes are corrupt (a string length beyond the message) is skipped, counted and
// named; the stream goes on with the next one.
TEST(BagReader, UnreadableMessageIsSkippedAndCounted) {
  ScratchDir dir;
  const std::string path = (dir / "corrupt.bag").string();
  {
    BagWriter w(path);
    for (int k = 0; k < 3; ++k) w.WriteScan("/c", 1.0 + k, 1.0 + k, Scan(k));
  }
  std::string bytes = ReadAll(path);
  const std::string name("\x09\x00\x00\x00intensity", 13);
  const std::size_t at = bytes.find(name);  // the field name of message 0
  ASSERT_NE(at, std::string::npos);
  ASSERT_NE(bytes.find(name, at + 1), std::string::npos);
  bytes[at + 1] = '\x10';  // 4105 bytes: past the message's end
  WriteAll(path, bytes);
  BagReader r(path);
  r.Select({{"/c", {kPointCloud2}}});
  MessageRef m;
  std::vector<std::size_t> indices;
  while (r.Next(&m)) indices.push_back(m.index);
  EXPECT_EQ(indices, (std::vector<std::size_t>{1, 2}));
  EXPECT_EQ(r.stats().unreadable, 1u);
  ASSERT_EQ(r.warnings().size(), 1u);
  EXPECT_NE(r.warnings()[0].find(path + ": topic /c, message 0: unreadable"), std::string::npos)
      << r.warnings()[0];
}

TEST(BagReader, NanosecondStampsAreExact) {
  // Absolute stamps (a EuRoC recording's) in integer ns: the stream gives them back exactly,
  // which doubles of seconds since 1970 cannot (their spacing there is ~0.24 us).
  ScratchDir dir;
  const std::string path = (dir / "ns.bag").string();
  const std::int64_t t0 = 1403715273262142976LL;
  {
    BagWriter w(path);
    sensor::ImuSample s;
    w.WriteImuNs("/imu", t0 + 7, t0 + 1, s);
    w.WriteImageNs("/cam", t0 + 5000003, t0 + 5000001, 2, 1, "mono8", {7, 9});
    EXPECT_THROW(w.WriteImuNs("/imu", 0, 0, s), BagError);  // receive time 0 is not a ROS time
  }
  BagReader r(path);
  r.Select({{"/imu", {kImu}}, {"/cam", {kImage}}}, StampSource::kHeader);
  MessageRef m;
  ASSERT_TRUE(r.Next(&m));
  EXPECT_EQ(m.topic, "/imu");
  EXPECT_EQ(m.header_ns, t0 + 1);
  EXPECT_EQ(m.receive_ns, t0 + 7);
  EXPECT_EQ(m.stamp_ns, t0 + 1);
  ASSERT_TRUE(r.Next(&m));
  EXPECT_EQ(m.stamp_ns, t0 + 5000001);
  GrayImage image;
  std::string error;
  ASSERT_TRUE(r.ReadImage(&image, &error)) << error;
  EXPECT_EQ(image.pixels, (std::vector<std::uint8_t>{7, 9}));
  r.Select({{"/cam", {kImage}}}, StampSource::kReceive);
  ASSERT_TRUE(r.Next(&m));
  EXPECT_EQ(m.stamp_ns, t0 + 5000003);
}

TEST(BagWriter, RefusesToOverwrite) {
  ScratchDir dir;
  const std::string path = WriteSmallBag(dir);
  EXPECT_THROW(BagWriter w(path), BagError);
  EXPECT_EQ(BagReader(path).info().messages, 33u);
}

}  // namespace
}  // namespace bag
}  // namespace plucker
