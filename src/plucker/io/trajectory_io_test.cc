#include "plucker/io/trajectory_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace io {
namespace {

std::string TempPath(const std::string& stem) {
  return ::testing::TempDir() + "/plucker_traj_" + stem + "_" +
         std::to_string(::testing::UnitTest::GetInstance()->random_seed());
}

// Expects ParseTrajectory to throw a TrajectoryParseError at `line` whose text contains `what`.
void ExpectParseError(const std::string& text, TrajectoryFormat format, int line,
                      const std::string& what) {
  try {
    ParseTrajectory(text, "f.txt", format);
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const TrajectoryParseError& e) {
    EXPECT_EQ(e.file(), "f.txt");
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find("f.txt:" + std::to_string(line) + ": "), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

const char kKittiIdentity[] = "1 0 0 0 0 1 0 0 0 0 1 0\n";

TEST(TrajectoryIo, ParsesKittiRowMajor) {
  const Trajectory t = ParseTrajectory(std::string(kKittiIdentity) + "0 -1 0 1  1 0 0 2  0 0 1 3\n",
                                       "k.txt", TrajectoryFormat::kAuto);
  ASSERT_EQ(t.poses.size(), 2u);
  EXPECT_TRUE(t.times.empty());
  EXPECT_LT((t.poses[1].translation() - Eigen::Vector3d(1, 2, 3)).norm(), 1e-15);
  Eigen::Matrix3d R;
  R << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  EXPECT_LT((t.poses[1].RotationMatrix() - R).norm(), 1e-15);
}

TEST(TrajectoryIo, ParsesTumWithCommentsAndCrLf) {
  const Trajectory t = ParseTrajectory(
      "# timestamp tx ty tz qx qy qz qw\r\n\r\n1.5 1 2 3 0 0 0.247403959 0.968912422\r\n"
      "  # indented comment\n2.0 4 5 6 0 0 0 1\n",
      "t.txt", TrajectoryFormat::kAuto);
  ASSERT_EQ(t.poses.size(), 2u);
  EXPECT_EQ(t.times, (std::vector<double>{1.5, 2.0}));
  EXPECT_LT((t.poses[0].translation() - Eigen::Vector3d(1, 2, 3)).norm(), 1e-15);
  // qz = sin(0.25), qw = cos(0.25): a rotation of 0.5 rad about z.
  EXPECT_NEAR(Eigen::AngleAxisd(t.poses[0].rotation()).angle(), 0.5, 1e-8);
  EXPECT_NEAR(t.poses[0].rotation().z(), std::sin(0.25), 1e-8);
}

TEST(TrajectoryIo, KittiRoundTripIsExact) {
  verify::Rng rng(3);
  std::vector<SE3d> poses;
  for (int i = 0; i < 50; ++i) poses.push_back(verify::RandomPose(rng));
  const std::string path = TempPath("kitti");
  WriteKittiPoses(path, poses);
  const Trajectory back = ReadTrajectory(path);
  std::remove(path.c_str());
  ASSERT_EQ(back.poses.size(), poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    EXPECT_LT((back.poses[i].Matrix() - poses[i].Matrix()).cwiseAbs().maxCoeff(), 1e-14);
  }
}

TEST(TrajectoryIo, KittiPosesWithGapsRoundTrip) {
  verify::Rng rng(4);
  std::vector<std::optional<SE3d>> poses = {verify::RandomPose(rng), std::nullopt,
                                            verify::RandomPose(rng), std::nullopt};
  const std::string path = TempPath("gaps");
  WriteKittiPosesWithGaps(path, poses);
  const std::vector<std::optional<SE3d>> back = ReadKittiPosesWithGaps(path);
  ASSERT_EQ(back.size(), 4u);
  int compared = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    ASSERT_EQ(back[i].has_value(), poses[i].has_value()) << i;
    if (!poses[i]) continue;
    EXPECT_LT((back[i]->Matrix() - poses[i]->Matrix()).cwiseAbs().maxCoeff(), 1e-14);
    ++compared;
  }
  EXPECT_EQ(compared, 2);
  // A NaN among numbers is not a gap, and a wrong field count names the line.
  std::ofstream(path) << "1 0 0 0 0 1 0 0 0 0 1 nan\n";
  EXPECT_THROW(ReadKittiPosesWithGaps(path), IoError);
  std::ofstream(path) << kKittiIdentity << "nan nan nan\n";
  try {
    ReadKittiPosesWithGaps(path);
    ADD_FAILURE() << "no error";
  } catch (const TrajectoryParseError& e) {
    EXPECT_EQ(e.line(), 2) << e.what();
  }
  std::remove(path.c_str());
  EXPECT_THROW(ReadKittiPosesWithGaps(path), IoError);  // missing
}

TEST(TrajectoryIo, TumRoundTripIsExact) {
  verify::Rng rng(4);
  std::vector<SE3d> poses;
  std::vector<double> times;
  for (int i = 0; i < 50; ++i) {
    poses.push_back(verify::RandomPose(rng));
    times.push_back(1305031102.175304 + 0.1 * i);
  }
  const std::string path = TempPath("tum");
  WriteTumTrajectory(path, times, poses);
  const Trajectory back = ReadTrajectory(path, TrajectoryFormat::kTum);
  std::remove(path.c_str());
  ASSERT_EQ(back.poses.size(), poses.size());
  EXPECT_EQ(back.times, times);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    EXPECT_LT((back.poses[i].Matrix() - poses[i].Matrix()).cwiseAbs().maxCoeff(), 1e-14);
  }
}

TEST(TrajectoryIo, WriteTumRejectsSizeMismatch) {
  EXPECT_THROW(WriteTumTrajectory(TempPath("bad"), {1.0}, {}), IoError);
}

TEST(TrajectoryIo, ReorthonormalisesSmallErrorsRejectsLarge) {
  // 1e-5 off: repaired to an exact rotation.
  const Trajectory t =
      ParseTrajectory("1.00001 0 0 0 0 1 0 0 0 0 0.99999 0\n", "f.txt", TrajectoryFormat::kKitti);
  const Eigen::Matrix3d R = t.poses[0].RotationMatrix();
  EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  ExpectParseError(std::string(kKittiIdentity) + "1.1 0 0 0 0 1 0 0 0 0 1 0\n",
                   TrajectoryFormat::kAuto, 2, "not a rotation");
  // A reflection is orthonormal but not a rotation.
  ExpectParseError("-1 0 0 0 0 1 0 0 0 0 1 0\n", TrajectoryFormat::kAuto, 1, "not a rotation");
  ExpectParseError("0 0 0 0 0 0 0 0 0 0 0 0\n", TrajectoryFormat::kAuto, 1, "not a rotation");
}

TEST(TrajectoryIo, QuaternionNormalisedOrRejected) {
  const Trajectory t = ParseTrajectory("0 0 0 0 0 0 0 1.0004\n", "f.txt", TrajectoryFormat::kTum);
  EXPECT_NEAR(t.poses[0].rotation().norm(), 1.0, 1e-15);
  ExpectParseError("0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 0\n", TrajectoryFormat::kTum, 2,
                   "zero quaternion");
  ExpectParseError("0 0 0 0 0 0 0 2\n", TrajectoryFormat::kTum, 1, "quaternion norm");
}

TEST(TrajectoryIo, ReportsFileLineAndProblem) {
  ExpectParseError("1 2 3\n", TrajectoryFormat::kAuto, 1, "cannot detect the format");
  ExpectParseError(std::string(kKittiIdentity) + "1 0 0 0 0 1 0 0 0 0 1\n", TrajectoryFormat::kAuto,
                   2, "11 fields, expected 12");
  ExpectParseError("# c\n0 0 0 0 0 0 0 1\n1 0 0 0 0 0 1\n", TrajectoryFormat::kAuto, 3,
                   "7 fields, expected 8");
  ExpectParseError("1 0 0 x 0 1 0 0 0 0 1 0\n", TrajectoryFormat::kKitti, 1,
                   "field 4 is not a number: 'x'");
  ExpectParseError("1 0 0 1.5abc 0 1 0 0 0 0 1 0\n", TrajectoryFormat::kKitti, 1, "not a number");
  ExpectParseError("1 0 0 nan 0 1 0 0 0 0 1 0\n", TrajectoryFormat::kKitti, 1, "not finite");
  ExpectParseError("0 inf 0 0 0 0 0 1\n", TrajectoryFormat::kTum, 1, "not finite");
  ExpectParseError("0 1e999 0 0 0 0 0 1\n", TrajectoryFormat::kTum, 1, "not finite");
  ExpectParseError("2 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n", TrajectoryFormat::kTum, 2,
                   "before the previous");
  // Forcing KITTI on a TUM file names the field count.
  ExpectParseError("0 0 0 0 0 0 0 1\n", TrajectoryFormat::kKitti, 1, "8 fields, expected 12");
}

TEST(TrajectoryIo, EqualTimestampsAreAllowed) {
  EXPECT_EQ(ParseTrajectory("1 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n", "f", TrajectoryFormat::kTum)
                .poses.size(),
            2u);
}

TEST(TrajectoryIo, EmptyFileAndMissingFileAreErrorsNamingTheFile) {
  for (const std::string text : {"", "\n\n", "# only a comment\n"}) {
    try {
      ParseTrajectory(text, "empty.txt", TrajectoryFormat::kAuto);
      ADD_FAILURE() << "no error";
    } catch (const IoError& e) {
      EXPECT_EQ(e.path(), "empty.txt");
      EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos);
    }
  }
  try {
    ReadTrajectory("/nonexistent/dir/poses.txt");
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/poses.txt"), std::string::npos);
  }
}

TEST(TrajectoryIo, ReadTimes) {
  const std::string path = TempPath("times");
  { std::ofstream(path) << "0.000000e+00\n1.036116e-01\n2.072240e-01\n"; }
  const std::vector<double> t = ReadTimes(path);
  ASSERT_EQ(t.size(), 3u);
  EXPECT_DOUBLE_EQ(t[1], 0.1036116);
  { std::ofstream(path) << "0.1\n0.0\n"; }
  EXPECT_THROW(ReadTimes(path), TrajectoryParseError);
  std::remove(path.c_str());
}

TEST(TrajectoryIo, FormatNames) {
  for (TrajectoryFormat f :
       {TrajectoryFormat::kAuto, TrajectoryFormat::kKitti, TrajectoryFormat::kTum}) {
    EXPECT_EQ(ParseTrajectoryFormat(FormatName(f)), f);
  }
  EXPECT_THROW(ParseTrajectoryFormat("euroc"), std::invalid_argument);
}

TEST(TrajectoryIo, ReadsSharedKittiGroundTruth) {
  const std::string path = std::string(PLUCKER_SHARED_DATA_DIR) + "/kitti-odometry-00/poses/00.txt";
  if (!std::ifstream(path)) GTEST_SKIP() << "shared data absent: " << path;
  const Trajectory t = ReadTrajectory(path);
  EXPECT_EQ(t.poses.size(), 16u);
  EXPECT_TRUE(t.times.empty());
}

TEST(TrajectoryIo, NanosecondsAsExactDecimalSeconds) {
  EXPECT_EQ(FormatNanosecondsAsSeconds(1403638538577829376LL), "1403638538.577829376");
  EXPECT_EQ(FormatNanosecondsAsSeconds(0), "0.000000000");
  EXPECT_EQ(FormatNanosecondsAsSeconds(5), "0.000000005");
  EXPECT_EQ(FormatNanosecondsAsSeconds(-1500000000LL), "-1.500000000");
  EXPECT_EQ(FormatNanosecondsAsSeconds(INT64_MIN), "-9223372036.854775808");
}

TEST(TrajectoryIo, TumOnTheDatasetClockKeepsEveryNanosecond) {
  const std::int64_t origin = 1403638538577829376LL;
  // Offsets of a long recording (hours), as seconds since the origin the way the readers give
  // them: (ns - origin) * 1e-9.
  const std::vector<std::int64_t> offsets = {0, 1, 49999999, 50000001, 3600123456789LL};
  std::vector<double> times;
  std::vector<SE3d> poses;
  for (std::int64_t d : offsets) {
    times.push_back(static_cast<double>(d) * 1e-9);
    poses.push_back(SE3d(Eigen::Quaterniond(0.5, 0.5, -0.5, 0.5), Eigen::Vector3d(1, -2, 3)));
  }
  const std::string path = TempPath("clock") + ".tum";
  WriteTumTrajectoryOnClock(path, origin, times, poses, {"T_w_b: body frame"});
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "# T_w_b: body frame");
  std::getline(in, line);
  EXPECT_EQ(line, "# stamps: seconds on the recording's own clock");
  std::getline(in, line);
  EXPECT_EQ(line, "# t tx ty tz qx qy qz qw");
  for (std::int64_t d : offsets) {
    ASSERT_TRUE(std::getline(in, line));
    EXPECT_EQ(line.substr(0, line.find(' ')), FormatNanosecondsAsSeconds(origin + d));
  }
  const Trajectory back = ReadTrajectory(path);
  ASSERT_EQ(back.poses.size(), offsets.size());
  EXPECT_NEAR(back.times.back(), 1403638538.577829376 + 3600.123456789, 1e-6);
  EXPECT_TRUE(back.poses[0].translation().isApprox(Eigen::Vector3d(1, -2, 3)));
  EXPECT_THROW(WriteTumTrajectoryOnClock(path, origin, {0.0}, {}), IoError);
  EXPECT_THROW(WriteTumTrajectoryOnClock(path, origin, {std::nan("")}, {SE3d()}), IoError);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace io
}  // namespace plucker
