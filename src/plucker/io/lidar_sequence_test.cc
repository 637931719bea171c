#include "plucker/io/lidar_sequence.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "plucker/io/io_test_utils.h"
#include "plucker/io/kitti_lidar.h"
#include "plucker/io/pcd.h"

namespace plucker {
namespace io {
namespace {

namespace fs = std::filesystem;

class LidarSequenceTest : public ::testing::Test {
 protected:
  static LidarScan Scan(int n, double offset) {
    LidarScan s;
    for (int i = 0; i < n; ++i) {
      s.points.emplace_back(offset + i, 1.0, -1.0);
      s.intensity.push_back(0.5f);
    }
    return s;
  }
  void Write(const fs::path& p, const std::string& bytes) {
    fs::create_directories(p.parent_path());
    WriteFileAtomically(p.string(), bytes);
  }
  // velodyne/ with frames 0, 1, 2 (truncated), 3 absent, 4, 5 (empty).
  void MakeKitti(const fs::path& seq) {
    fs::create_directories(seq / "velodyne");
    WriteKittiBin((seq / "velodyne/000000.bin").string(), Scan(10, 0));
    WriteKittiBin((seq / "velodyne/000001.bin").string(), Scan(11, 1));
    Write(seq / "velodyne/000002.bin", SerializeKittiBin(Scan(5, 2)).substr(0, 70));
    WriteKittiBin((seq / "velodyne/000004.bin").string(), Scan(14, 4));
    Write(seq / "velodyne/000005.bin", "");
    Write(seq / "calib.txt", "P0: 1 0 0 0 0 1 0 0 0 0 1 0\nTr: 0 -1 0 0.1 0 0 -1 0.2 1 0 0 0.3\n");
    WriteKittiTimes((seq / "times.txt").string(), {0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6});
  }
  const testing::ScratchDir scratch_;
  const fs::path& dir_ = scratch_.path();
};

TEST_F(LidarSequenceTest, KittiSequenceWithGapsAndBadFrames) {
  MakeKitti(dir_);
  const LidarSequence seq = LidarSequence::Open(dir_.string());
  EXPECT_EQ(seq.format(), LidarSequence::Format::kKittiBin);
  ASSERT_EQ(seq.size(), 6u);
  EXPECT_EQ(seq.num_missing(), 1u);
  EXPECT_TRUE(seq.frame(3).missing);
  EXPECT_EQ(fs::path(seq.frame(3).path).filename(), "000003.bin");
  EXPECT_TRUE(seq.has_calib());
  ASSERT_TRUE(seq.T_cam0_velo().has_value());
  EXPECT_NEAR(seq.T_cam0_velo()->translation().z(), 0.3, 1e-15);
  ASSERT_EQ(seq.times().size(), 6u);
  EXPECT_FALSE(seq.has_point_time());
  EXPECT_NE(seq.description().find("6 frames (1 missing)"), std::string::npos) << seq.description();

  LidarScan scan;
  std::string error;
  ASSERT_TRUE(seq.Read(4, &scan, &error)) << error;
  EXPECT_EQ(scan.size(), 14u);
  EXPECT_DOUBLE_EQ(scan.timestamp, 0.4);
  struct Bad {
    std::size_t index;
    const char* file;
    const char* problem;
  } bad[] = {{2, "000002.bin", "truncated"},
             {3, "000003.bin", "missing frame"},
             {5, "000005.bin", "empty scan"}};
  for (const Bad& b : bad) {
    EXPECT_FALSE(seq.Read(b.index, &scan, &error));
    EXPECT_NE(error.find(b.file), std::string::npos) << error;
    EXPECT_NE(error.find(b.problem), std::string::npos) << error;
  }
  EXPECT_FALSE(seq.Read(99, &scan, &error));
  // A frame that disappears after Open is a per-frame error, not an exception.
  fs::remove(dir_ / "velodyne/000001.bin");
  EXPECT_FALSE(seq.Read(1, &scan, &error));
  EXPECT_NE(error.find("cannot open"), std::string::npos) << error;
}

TEST_F(LidarSequenceTest, DatasetRootWithSequence) {
  MakeKitti(dir_ / "sequences/07");
  const LidarSequence seq = LidarSequence::Open(dir_.string(), "07");
  EXPECT_EQ(seq.size(), 6u);
  try {
    LidarSequence::Open(dir_.string());
    ADD_FAILURE() << "dataset root without a sequence accepted";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("sequence"), std::string::npos);
  }
  EXPECT_THROW(LidarSequence::Open(dir_.string(), "08"), IoError);
  // The velodyne folder itself also works (calib/times from its parent).
  EXPECT_TRUE(LidarSequence::Open((dir_ / "sequences/07/velodyne").string()).T_cam0_velo());
}

TEST_F(LidarSequenceTest, CalibWithoutTrAndNoTimes) {
  MakeKitti(dir_);
  Write(dir_ / "calib.txt", "P0: 1 0 0 0 0 1 0 0 0 0 1 0\n");
  fs::remove(dir_ / "times.txt");
  const LidarSequence seq = LidarSequence::Open(dir_.string());
  EXPECT_TRUE(seq.has_calib());
  EXPECT_FALSE(seq.T_cam0_velo().has_value());
  EXPECT_TRUE(seq.times().empty());
  fs::remove(dir_ / "calib.txt");
  EXPECT_FALSE(LidarSequence::Open(dir_.string()).has_calib());
}

TEST_F(LidarSequenceTest, FolderErrors) {
  EXPECT_THROW(LidarSequence::Open((dir_ / "absent").string()), IoError);
  Write(dir_ / "file.txt", "x");
  EXPECT_THROW(LidarSequence::Open((dir_ / "file.txt").string()), IoError);
  EXPECT_THROW(LidarSequence::Open(dir_.string()), IoError);  // no frames
  MakeKitti(dir_ / "s");
  Write(dir_ / "s/calib.txt", "Tr: 1 0 0 0 0 1 0 0 0 0 1\n");
  EXPECT_THROW(LidarSequence::Open((dir_ / "s").string()), IoError);  // malformed Tr
  MakeKitti(dir_ / "t");
  WriteKittiTimes((dir_ / "t/times.txt").string(), {0.0, 0.1});
  try {
    LidarSequence::Open((dir_ / "t").string());
    ADD_FAILURE() << "short times.txt accepted";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("times.txt"), std::string::npos) << e.what();
  }
  if (geteuid() != 0) {  // root reads every folder
    fs::create_directories(dir_ / "locked/velodyne");
    fs::permissions(dir_ / "locked/velodyne", fs::perms::none);
    EXPECT_THROW(LidarSequence::Open((dir_ / "locked").string()), IoError);
    fs::permissions(dir_ / "locked/velodyne", fs::perms::owner_all);
  }
}

TEST_F(LidarSequenceTest, PcdFolderSortedByNameWithStampTimes) {
  LidarScan s = Scan(5, 0);
  s.time = {0.0, 0.01, 0.02, 0.03, 0.04};
  WritePcd((dir_ / "1600000000.20.pcd").string(), s);
  WritePcd((dir_ / "1600000000.10.pcd").string(), s);
  WritePcd((dir_ / "1600000000.30.pcd").string(), s);
  const LidarSequence seq = LidarSequence::Open(dir_.string());
  EXPECT_EQ(seq.format(), LidarSequence::Format::kPcd);
  ASSERT_EQ(seq.size(), 3u);
  EXPECT_TRUE(seq.has_point_time());
  ASSERT_EQ(seq.times().size(), 3u);
  EXPECT_DOUBLE_EQ(seq.times()[0], 1600000000.10);
  EXPECT_EQ(fs::path(seq.frame(2).path).filename(), "1600000000.30.pcd");
  LidarScan scan;
  std::string error;
  ASSERT_TRUE(seq.Read(1, &scan, &error)) << error;
  EXPECT_EQ(scan.time.size(), 5u);
}

// One scan read frame after frame (as the apps do): each read replaces every channel.
TEST_F(LidarSequenceTest, ReadingIntoTheSameScanReplacesIt) {
  fs::create_directories(dir_ / "pcd");
  LidarScan with_time = Scan(6, 0);
  with_time.ring = {0, 0, 0, 1, 1, 1};
  with_time.time = {0.0, 0.01, 0.02, 0.03, 0.04, 0.05};
  WritePcd((dir_ / "pcd/000000.pcd").string(), with_time);
  WritePcd((dir_ / "pcd/000001.pcd").string(), Scan(3, 7));
  WritePcd((dir_ / "pcd/000002.pcd").string(), with_time);
  const LidarSequence seq = LidarSequence::Open(dir_.string());
  LidarScan scan;
  std::string error;
  int reads = 0;
  for (std::size_t i : {0, 1, 2, 1}) {
    ASSERT_TRUE(seq.Read(i, &scan, &error)) << error;
    ++reads;
    const bool full = i != 1;
    ASSERT_EQ(scan.size(), full ? 6u : 3u);
    EXPECT_EQ(scan.points[0].x(), full ? 0.0 : 7.0);
    EXPECT_EQ(scan.ring.size(), full ? 6u : 0u);
    EXPECT_EQ(scan.time.size(), full ? 6u : 0u);
    EXPECT_EQ(scan.intensity.size(), scan.size());
  }
  EXPECT_EQ(reads, 4);
}

TEST_F(LidarSequenceTest, SimLayoutPrefersPcd) {
  MakeKitti(dir_);
  LidarScan s = Scan(5, 0);
  s.time = {0.0, 0.01, 0.02, 0.03, 0.04};
  fs::create_directories(dir_ / "pcd");
  WritePcd((dir_ / "pcd/000000.pcd").string(), s);
  WritePcd((dir_ / "pcd/000002.pcd").string(), s);
  const LidarSequence seq = LidarSequence::Open(dir_.string());
  EXPECT_EQ(seq.format(), LidarSequence::Format::kPcd);
  EXPECT_EQ(seq.size(), 3u);
  EXPECT_TRUE(seq.frame(1).missing);
  EXPECT_TRUE(seq.has_point_time());
  EXPECT_EQ(seq.times().size(), 3u);
}

TEST(LidarSequenceReal, KittiExtract) {
  const fs::path root = fs::path(PLUCKER_SHARED_DATA_DIR) / "kitti-odometry-00";
  if (!fs::exists(root / "sequences/00/velodyne")) GTEST_SKIP() << "no KITTI extract at " << root;
  const LidarSequence seq = LidarSequence::Open(root.string(), "00");
  EXPECT_EQ(seq.size(), 16u);
  EXPECT_EQ(seq.num_missing(), 0u);
  EXPECT_TRUE(seq.T_cam0_velo().has_value());
  EXPECT_EQ(seq.times().size(), 16u);
  LidarScan scan;
  std::string error;
  for (std::size_t i = 0; i < seq.size(); i += 5) {
    ASSERT_TRUE(seq.Read(i, &scan, &error)) << error;
    EXPECT_GT(scan.size(), 100000u);
    EXPECT_LT(scan.size(), 140000u);
  }
}

}  // namespace
}  // namespace io
}  // namespace plucker
