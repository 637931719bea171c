// ROS 2 .db3 bags through the same BagReader/BagWriter as ROS 1 bags.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <fstream>

#include "plucker/bag/bag_reader.h"
#include "plucker/bag/bag_test_utils.h"
#include "plucker/bag/bag_writer.h"
#include "plucker/io/io_test_utils.h"

namespace plucker {
namespace bag {
namespace {

using io::testing::ScratchDir;
using testing::ErrorOf;
using testing::Scan;

// As bag_reader_test's small bag: scans at 10 Hz (received 5 ms late), IMU at 100 Hz (50 ms
// late), an odd-length frame_id so that the CDR alignment after it matters.
void WriteSmall(const std::string& path) {
  BagWriterOptions options;
  options.frame_id = "lidar";
  BagWriter w(path, options);
  for (int k = 0; k < 3; ++k) w.WriteScan("/points", 1.005 + 0.1 * k, 1.0 + 0.1 * k, Scan(k));
  for (int k = 0; k < 30; ++k) {
    sensor::ImuSample s;
    s.t = 1.0 + 0.01 * k;
    s.gyro = Eigen::Vector3d(0.1 * k, 0, 0);
    s.accel = Eigen::Vector3d(0, 0, 9.81);
    w.WriteImu("/imu", s.t + 0.05, s);
  }
  w.WriteImage("/cam", 2.0, 2.0, 2, 1, "rgb8", {255, 0, 0, 0, 0, 255});
  w.WriteImage("/cam", 2.1, 2.1, 1, 1, "16UC1", {1, 2});
  w.WriteCompressed("/jpeg", 2.0, 2.0, "jpeg", {0xff, 0xd8});
  w.Close();
}

void Sql(const std::string& path, const char* sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, sql, nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
  sqlite3_close(db);
}

TEST(Db3Reader, InfoStreamAndDecodeAsForRos1) {
  ScratchDir dir;
  const std::string db3 = (dir / "small.db3").string(), ros1 = (dir / "small.bag").string();
  WriteSmall(db3);
  WriteSmall(ros1);
  BagReader a(db3), b(ros1);
  EXPECT_EQ(a.info().format, "rosbag2 SQLite3 (.db3)");
  ASSERT_EQ(a.info().topics.size(), 4u);
  EXPECT_EQ(a.info().topics[1].topic, "/imu");
  EXPECT_EQ(a.info().topics[1].type, "sensor_msgs/msg/Imu");
  EXPECT_EQ(a.info().topics[1].messages, 30u);
  EXPECT_EQ(a.info().messages, b.info().messages);
  EXPECT_EQ(a.info().start_s, b.info().start_s);
  EXPECT_EQ(a.info().end_s, b.info().end_s);
  for (StampSource stamp : {StampSource::kHeader, StampSource::kReceive}) {
    const std::vector<TopicRequest> req = {{"/points", {kPointCloud2}}, {"/imu", {kImu}}};
    a.Select(req, stamp), b.Select(req, stamp);
    MessageRef ma, mb;
    std::size_t n = 0;
    while (a.Next(&ma)) {
      ASSERT_TRUE(b.Next(&mb));
      EXPECT_EQ(ma.topic, mb.topic);
      EXPECT_EQ(ma.index, mb.index);
      EXPECT_EQ(ma.stamp_ns, mb.stamp_ns);
      EXPECT_EQ(ma.receive_s, mb.receive_s);
      EXPECT_EQ(ma.header_s, mb.header_s);
      if (ma.type == kImu) {
        sensor::ImuSample sa, sb;
        ASSERT_TRUE(a.ReadImu(&sa, nullptr) && b.ReadImu(&sb, nullptr));
        EXPECT_EQ(sa.t, sb.t);
        EXPECT_EQ(sa.gyro, sb.gyro);
        EXPECT_EQ(sa.accel, sb.accel);
      } else {
        sensor::LidarScan sa, sb;
        ASSERT_TRUE(a.ReadScan(&sa, nullptr) && b.ReadScan(&sb, nullptr));
        EXPECT_EQ(sa.points, sb.points);
        EXPECT_EQ(sa.intensity, sb.intensity);
        EXPECT_EQ(sa.timestamp, sb.timestamp);
      }
      ++n;
    }
    EXPECT_FALSE(b.Next(&mb));
    EXPECT_EQ(n, 33u);
  }
  a.Select({{"/cam", {kImage}}, {"/jpeg", {kCompressedImage}}});
  ASSERT_TRUE(a.Next(nullptr));
  GrayImage image;
  ASSERT_TRUE(a.ReadImage(&image, nullptr));
  EXPECT_EQ(image.width, 2);
  EXPECT_EQ(image.pixels[0], 76);  // red, OpenCV's weights
  ASSERT_TRUE(a.Next(nullptr));
  std::string format, error;
  std::vector<std::uint8_t> bytes;
  ASSERT_TRUE(a.ReadCompressed(&format, &bytes, nullptr));
  EXPECT_EQ(format, "jpeg");
  ASSERT_TRUE(a.Next(nullptr));
  EXPECT_FALSE(a.ReadImage(&image, &error));
  EXPECT_NE(error.find("small.db3: topic /cam, message 1: image encoding '16UC1' is not supported"),
            std::string::npos)
      << error;
}

TEST(Db3Reader, Rosbag2FolderAndItsProblems) {
  ScratchDir dir;
  std::filesystem::create_directories(dir / "rec");
  const std::string folder = (dir / "rec").string();
  EXPECT_NE(ErrorOf(folder).find("rec: a folder, but not a rosbag2 folder (no metadata.yaml)"),
            std::string::npos);
  std::ofstream(dir / "rec" / "metadata.yaml") << "rosbag2_bagfile_information:\n"
                                                  "  storage_identifier: sqlite3\n"
                                                  "  compression_format: \"\"\n";
  EXPECT_NE(ErrorOf(folder).find("rosbag2 folder without a .db3 file"), std::string::npos);
  WriteSmall((dir / "rec" / "rec_0.db3").string());
  const BagReader r(folder);
  EXPECT_EQ(r.info().topics.size(), 4u);
  WriteSmall((dir / "rec" / "rec_1.db3").string());
  EXPECT_NE(ErrorOf(folder).find("split rosbag2 (2 .db3 files) is not read"), std::string::npos);
  std::ofstream(dir / "rec" / "metadata.yaml") << "  compression_format: zstd\n";
  EXPECT_NE(ErrorOf(folder).find("compressed rosbag2 (zstd) is not read"), std::string::npos);
}

TEST(Db3Reader, NotARosbag2DatabaseMissingTopicWrongTypeBadPayloads) {
  ScratchDir dir;
  const std::string other = (dir / "other.db3").string();
  Sql(other, "CREATE TABLE topics(id INTEGER); CREATE TABLE things(x INTEGER);");
  EXPECT_NE(ErrorOf(other).find("other.db3: an SQLite database but not a rosbag2 .db3 (no "
                                "messages table)"),
            std::string::npos)
      << ErrorOf(other);
  const std::string path = (dir / "small.db3").string();
  WriteSmall(path);
  BagReader r(path);
  try {
    r.Select({{"/velodyne_points", {kPointCloud2}}});
    FAIL();
  } catch (const BagError& e) {
    EXPECT_NE(std::string(e.what()).find("small.db3: no topic /velodyne_points; the bag has: /cam "
                                         "(sensor_msgs/msg/Image), /imu (sensor_msgs/msg/Imu)"),
              std::string::npos)
        << e.what();
  }
  try {
    r.Select({{"/imu", {kPointCloud2}}});
    FAIL();
  } catch (const BagError& e) {
    EXPECT_NE(std::string(e.what()).find("topic /imu has type sensor_msgs/msg/Imu, expected "
                                         "sensor_msgs/PointCloud2"),
              std::string::npos)
        << e.what();
  }
  // Truncated, big-endian and empty payloads: skipped, counted and named with topic and index.
  Sql(path,
      "UPDATE messages SET data = substr(data, 1, 30) WHERE id = 5;"
      "UPDATE messages SET data = X'00000000' || substr(data, 5) WHERE id = 6;"
      "UPDATE messages SET data = X'' WHERE id = 7;"
      "UPDATE topics SET serialization_format = 'json' WHERE name = '/jpeg';");
  BagReader bad(path);
  bad.Select({{"/imu", {kImu}}}, StampSource::kReceive);
  std::size_t n = 0;
  while (bad.Next(nullptr)) ++n;
  EXPECT_EQ(n, 27u);
  EXPECT_EQ(bad.stats().unreadable, 3u);
  ASSERT_EQ(bad.warnings().size(), 3u);
  EXPECT_NE(bad.warnings()[0].find("small.db3: topic /imu, message 1: cannot deserialise as "
                                   "sensor_msgs/msg/Imu: truncated"),
            std::string::npos)
      << bad.warnings()[0];
  EXPECT_NE(bad.warnings()[1].find("big-endian"), std::string::npos) << bad.warnings()[1];
  EXPECT_NE(bad.warnings()[2].find("message 3"), std::string::npos) << bad.warnings()[2];
  EXPECT_THROW(bad.Select({{"/jpeg", {kCompressedImage}}}), BagError);
  EXPECT_NE(ErrorOf((dir / "none.db3").string()).find("none.db3: no such file"), std::string::npos);
}

}  // namespace
}  // namespace bag
}  // namespace plucker
