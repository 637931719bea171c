#include "plucker/io/kitti_lidar.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>

#include "plucker/io/io_test_utils.h"

namespace plucker {
namespace io {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;

std::string Records(const std::vector<std::array<float, 4>>& recs) {
  std::string bytes(recs.size() * 16, '\0');
  for (std::size_t i = 0; i < recs.size(); ++i) std::memcpy(&bytes[16 * i], recs[i].data(), 16);
  return bytes;
}

void WriteRaw(const fs::path& p, const std::string& bytes) {
  WriteFileAtomically(p.string(), bytes);
}

TEST(KittiBin, ParsesRecords) {
  const LidarScan scan = ParseKittiBin(Records({{1, 2, 3, 0.5f}, {-4, 5.5f, -6, 1}}), "a.bin");
  ASSERT_EQ(scan.size(), 2u);
  EXPECT_EQ(scan.points[1], Eigen::Vector3d(-4, 5.5, -6));
  EXPECT_FLOAT_EQ(scan.intensity[0], 0.5f);
  EXPECT_TRUE(scan.ring.empty());
  EXPECT_TRUE(scan.time.empty());
}

// A reader keeps one scan across frames: parsing into it must replace every channel and reuse
// the memory (no reallocation when the new frame is not larger).
TEST(KittiBin, ParseIntoAScanReplacesItAndReusesItsMemory) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  LidarScan scan;
  ParseKittiBin(Records({{1, 2, 3, 0.5f}, {4, 5, 6, 1}, {7, 8, 9, nan}}), "a.bin", &scan);
  ASSERT_EQ(scan.size(), 3u);
  EXPECT_FLOAT_EQ(scan.intensity[2], 0.0f);  // non-finite intensity -> 0
  scan.ring = {0, 1, 2};                     // as the odometry leaves it (rings assigned in place)
  scan.time = {0.0, 0.01, 0.02};
  scan.timestamp = 5.0;
  const Eigen::Vector3d* data = scan.points.data();
  ScanReadStats stats;
  ParseKittiBin(Records({{-1, -2, -3, 0.25f}, {nan, 0, 0, 0}}), "b.bin", &scan, &stats);
  ASSERT_EQ(scan.size(), 1u);
  EXPECT_EQ(scan.points[0], Eigen::Vector3d(-1, -2, -3));
  ASSERT_EQ(scan.intensity.size(), 1u);
  EXPECT_FLOAT_EQ(scan.intensity[0], 0.25f);
  EXPECT_TRUE(scan.ring.empty());
  EXPECT_TRUE(scan.time.empty());
  EXPECT_EQ(scan.timestamp, 0.0);
  EXPECT_EQ(stats.points_in_file, 2u);
  EXPECT_EQ(stats.non_finite_dropped, 1u);
  EXPECT_EQ(scan.points.data(), data);  // same buffer
  EXPECT_THROW(ParseKittiBin(Records({{nan, 0, 0, 0}}), "c.bin", &scan), IoError);
}

TEST(KittiBin, ReadFileIntoReusesTheBuffer) {
  const ScratchDir scratch;
  const fs::path& dir = scratch.path();
  std::string big(100000, 'x'), small = "0123456789";
  WriteRaw(dir / "big", big);
  WriteRaw(dir / "small", small);
  WriteRaw(dir / "empty", "");
  std::string bytes;
  ReadFileInto((dir / "big").string(), &bytes);
  EXPECT_EQ(bytes, big);
  const char* data = bytes.data();
  ReadFileInto((dir / "small").string(), &bytes);
  EXPECT_EQ(bytes, small);
  EXPECT_EQ(bytes.data(), data);
  ReadFileInto((dir / "empty").string(), &bytes);
  EXPECT_TRUE(bytes.empty());
  std::string other_big(100000, 'y');  // a larger file after a smaller one: no stale byte left
  WriteRaw(dir / "other_big", other_big);
  ReadFileInto((dir / "small").string(), &bytes);
  ReadFileInto((dir / "other_big").string(), &bytes);
  EXPECT_EQ(bytes, other_big);
  EXPECT_EQ(ReadFileToString((dir / "big").string()), big);
  EXPECT_THROW(ReadFileInto((dir / "absent").string(), &bytes), IoError);
}

TEST(KittiBin, DropsAndCountsNonFinite) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  ScanReadStats stats;
  const LidarScan scan = ParseKittiBin(
      Records({{1, 2, 3, 0}, {nan, 0, 0, 0}, {0, inf, 0, 0}, {4, 5, 6, nan}}), "a", &stats);
  EXPECT_EQ(stats.points_in_file, 4u);
  EXPECT_EQ(stats.non_finite_dropped, 2u);
  ASSERT_EQ(scan.size(), 2u);
  EXPECT_FLOAT_EQ(scan.intensity[1], 0.0f);  // NaN intensity replaced, point kept
  for (const auto& p : scan.points) EXPECT_TRUE(p.allFinite());
}

TEST(KittiBin, ErrorsNameTheFile) {
  const ScratchDir scratch;
  const fs::path& dir = scratch.path();
  const fs::path truncated = dir / "truncated.bin", empty = dir / "empty.bin",
                 all_nan = dir / "nan.bin";
  WriteRaw(truncated, Records({{1, 2, 3, 4}}) + "abc");
  WriteRaw(empty, "");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  WriteRaw(all_nan, Records({{nan, nan, nan, 0}}));
  struct Case {
    fs::path path;
    const char* problem;
  } cases[] = {{truncated, "not a multiple of 16"},
               {empty, "empty scan"},
               {all_nan, "no finite point"},
               {dir / "absent.bin", "cannot open"}};
  for (const Case& c : cases) {
    try {
      ReadKittiBin(c.path.string());
      ADD_FAILURE() << "no error for " << c.path;
    } catch (const IoError& e) {
      EXPECT_EQ(e.path(), c.path.string());
      EXPECT_NE(std::string(e.what()).find(c.problem), std::string::npos) << e.what();
    }
  }
}

TEST(KittiBin, WriteReadRoundTrip) {
  const ScratchDir scratch;
  const fs::path& dir = scratch.path();
  LidarScan scan;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-50, 50);
  for (int i = 0; i < 1000; ++i) {
    scan.points.emplace_back(u(rng), u(rng), u(rng));
    scan.intensity.push_back(std::abs(u(rng)) / 50);
  }
  WriteKittiBin((dir / "x.bin").string(), scan);
  EXPECT_EQ(fs::file_size(dir / "x.bin"), 16000u);
  const LidarScan back = ReadKittiBin((dir / "x.bin").string());
  ASSERT_EQ(back.size(), scan.size());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    EXPECT_EQ(back.points[i], scan.points[i]);  // float values round-trip exactly
    EXPECT_EQ(back.intensity[i], scan.intensity[i]);
  }
}

TEST(KittiCalib, ParsesTrAndReorthonormalises) {
  const std::string text =
      "P0: 1 0 0 0 0 1 0 0 0 0 1 0\n"
      "Tr: 4.276802385584e-04 -9.999672484946e-01 -8.084491683471e-03 -1.198459927713e-02 "
      "-7.210626507497e-03 8.081198471645e-03 -9.999413164504e-01 -5.403984729748e-02 "
      "9.999738645903e-01 4.859485810390e-04 -7.206933692422e-03 -2.921968648686e-01\n";
  const std::optional<SE3d> T = ParseKittiCalibTr(text, "calib.txt");
  ASSERT_TRUE(T.has_value());
  const Eigen::Matrix3d R = T->RotationMatrix();
  EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(R(0, 1), -0.99996724849, 1e-6);
  EXPECT_NEAR(T->translation().z(), -0.2921968648686, 1e-12);
}

TEST(KittiCalib, MissingTrIsNotAnError) {
  EXPECT_FALSE(ParseKittiCalibTr("P0: 1 0 0 0 0 1 0 0 0 0 1 0\n", "calib.txt").has_value());
  EXPECT_FALSE(ParseKittiCalibTr("", "calib.txt").has_value());
}

TEST(KittiCalib, MalformedTrThrowsNamingFile) {
  const char* bad[] = {"Tr: 1 0 0 0 0 1 0 0 0 0 1\n",   "Tr: 1 0 0 0 0 1 0 0 0 0 1 0 7\n",
                       "Tr: 1 0 0 x 0 1 0 0 0 0 1 0\n", "Tr: 1 0 0 nan 0 1 0 0 0 0 1 0\n",
                       "Tr: 2 0 0 0 0 1 0 0 0 0 1 0\n", "Tr: -1 0 0 0 0 1 0 0 0 0 1 0\n"};
  for (const char* text : bad) {
    try {
      ParseKittiCalibTr(text, "my/calib.txt");
      ADD_FAILURE() << "accepted " << text;
    } catch (const IoError& e) {
      EXPECT_EQ(e.path(), "my/calib.txt");
    }
  }
}

TEST(KittiTimes, ParsesAndValidates) {
  EXPECT_EQ(ParseKittiTimes("0\n0.1\n\n0.2\n", "t").size(), 3u);
  EXPECT_THROW(ParseKittiTimes("0\n0.2\n0.1\n", "t"), IoError);  // decreasing
  EXPECT_THROW(ParseKittiTimes("0\nnan\n", "t"), IoError);
  EXPECT_THROW(ParseKittiTimes("0\ninf\n", "t"), IoError);
  EXPECT_THROW(ParseKittiTimes("0\n0.1 0.2\n", "t"), IoError);
  EXPECT_THROW(ParseKittiTimes("abc\n", "t"), IoError);
  try {
    ParseKittiTimes("0\n1\n0.5\n", "times.txt");
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("times.txt: line 3"), std::string::npos) << e.what();
  }
}

TEST(KittiTimes, WriteReadRoundTrip) {
  const ScratchDir scratch;
  const fs::path& dir = scratch.path();
  const std::vector<double> t = {0.0, 0.1037359, 0.2073381, 1e4};
  WriteKittiTimes((dir / "times.txt").string(), t);
  const std::vector<double> back = ReadKittiTimes((dir / "times.txt").string());
  ASSERT_EQ(back.size(), t.size());
  for (std::size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(back[i], t[i], 1e-9 * (1 + t[i]));
}

TEST(KittiBin, RealKittiScans) {
  const fs::path dir = fs::path(PLUCKER_SHARED_DATA_DIR) / "kitti-odometry-00/sequences/00";
  if (!fs::exists(dir / "velodyne/000000.bin")) GTEST_SKIP() << "no KITTI extract at " << dir;
  ScanReadStats stats;
  const LidarScan scan = ReadKittiBin((dir / "velodyne/000000.bin").string(), &stats);
  EXPECT_GT(scan.size(), 100000u);
  EXPECT_LT(scan.size(), 140000u);
  EXPECT_EQ(stats.non_finite_dropped, 0u);
  const std::optional<SE3d> Tr = ReadKittiCalibTr((dir / "calib.txt").string());
  ASSERT_TRUE(Tr.has_value());
  // velodyne x (forward) maps to camera z (forward).
  EXPECT_GT((Tr->RotationMatrix() * Eigen::Vector3d::UnitX()).z(), 0.99);
}

}  // namespace
}  // namespace io
}  // namespace plucker
