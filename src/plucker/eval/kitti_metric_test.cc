#include "plucker/eval/kitti_metric.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "plucker/eval/eval_test_utils.h"
#include "plucker/io/trajectory_io.h"

namespace plucker {
namespace eval {
namespace {

using testing::StraightLine;

// Hand count: frames 0..1000 at 1 m spacing, starts every 10 frames. With the devkit's strict
// rule dist[last] > dist[first] + L, last = first + L + 1 <= 1000, so first <= 999 - L.
int ExpectedSegments(int L) { return (999 - L) / 10 + 1; }

TEST(KittiMetric, StraightLineWithOnePercentScaleDriftGivesTheHandComputedError) {
  const std::vector<SE3d> gt = StraightLine(1001, 1.0);
  const std::vector<SE3d> est = StraightLine(1001, 1.01);  // 1 % too long every frame
  const KittiResult r = ComputeKittiMetric(gt, est);
  ASSERT_TRUE(r.has_segments());
  EXPECT_DOUBLE_EQ(r.path_length, 1000.0);
  // Each segment of length L ends L + 1 m further (strict >), its error is 0.01 (L + 1) m:
  // t_err = (L + 1) / L %.
  double sum = 0.0;
  int count = 0;
  for (const KittiLengthResult& l : r.per_length) {
    const int L = static_cast<int>(l.length);
    EXPECT_EQ(l.segment_count, ExpectedSegments(L)) << L;
    ASSERT_TRUE(l.translation_error_percent.has_value());
    EXPECT_NEAR(*l.translation_error_percent, (L + 1.0) / L, 1e-9) << L;
    EXPECT_NEAR(*l.rotation_error_deg_per_100m, 0.0, 1e-9);
    sum += ExpectedSegments(L) * (L + 1.0) / L;
    count += ExpectedSegments(L);
  }
  EXPECT_EQ(r.segment_count, count);
  EXPECT_NEAR(*r.translation_error_percent, sum / count, 1e-9);
  EXPECT_NEAR(*r.rotation_error_deg_per_m, 0.0, 1e-12);
}

TEST(KittiMetric, DevkitConventionsStepSizeTenAndStrictlyGreater) {
  // 1 m spacing makes every path distance an exact integer, so a segment length is hit exactly:
  // an implementation using ">=" would end at first + L (error exactly 1 %) and count one more
  // start per length; one starting every frame would have ~10x the segments.
  const KittiResult r = ComputeKittiMetric(StraightLine(1001, 1.0), StraightLine(1001, 1.01));
  for (const KittiSegment& s : r.segments) {
    EXPECT_EQ(s.first % 10, 0);
    EXPECT_EQ(s.last, s.first + static_cast<int>(s.length) + 1);
  }
  EXPECT_EQ(r.per_length[0].segment_count, 90);                         // ">=" would give 91
  EXPECT_NEAR(*r.per_length[0].translation_error_percent, 1.01, 1e-9);  // ">=" would give 1.00
  // The shortest sequence that has a 100 m segment: 102 frames (dist[101] = 101 > 100).
  EXPECT_FALSE(ComputeKittiMetric(StraightLine(101, 1.0), StraightLine(101, 1.0)).has_segments());
  EXPECT_EQ(ComputeKittiMetric(StraightLine(102, 1.0), StraightLine(102, 1.0)).segment_count, 1);
}

TEST(KittiMetric, ConstantYawDriftGivesTheHandComputedRotationError) {
  const double a = 1e-4;  // rad of heading error accumulated per frame
  const std::vector<SE3d> gt = StraightLine(401, 1.0);
  std::vector<SE3d> est;
  for (int i = 0; i < 401; ++i) {
    est.emplace_back(Eigen::Quaterniond(Eigen::AngleAxisd(a * i, Eigen::Vector3d::UnitY())),
                     gt[i].translation());
  }
  KittiOptions options;
  options.lengths = {100, 200};
  const KittiResult r = ComputeKittiMetric(gt, est, options);
  ASSERT_TRUE(r.has_segments());
  for (const KittiLengthResult& l : r.per_length) {
    // Angle of E over a segment = (L + 1) a, divided by L, in deg/100 m.
    const double expected = (l.length + 1) * a / l.length * 180.0 / M_PI * 100.0;
    EXPECT_NEAR(*l.rotation_error_deg_per_100m, expected, 1e-6 * expected) << l.length;
  }
}

TEST(KittiMetric, IdenticalTrajectoriesHaveZeroErrorNotNaN) {
  const std::vector<SE3d> gt = testing::Curve(2500);
  const KittiResult r = ComputeKittiMetric(gt, gt);
  ASSERT_TRUE(r.has_segments());
  EXPECT_LT(*r.translation_error_percent, 1e-12);
  // acos near 1 resolves only ~sqrt(2 eps) = 2e-8 rad; the devkit's clamp keeps it from NaN.
  EXPECT_LT(*r.rotation_error_deg_per_m, 1e-7);
}

TEST(KittiMetric, ShortSequenceReportsNoSegment) {
  const KittiResult r = ComputeKittiMetric(StraightLine(50, 1.0), StraightLine(50, 1.1));
  EXPECT_FALSE(r.has_segments());
  EXPECT_EQ(r.segment_count, 0);
  EXPECT_FALSE(r.translation_error_percent.has_value());
  EXPECT_FALSE(r.rotation_error_deg_per_m.has_value());
  for (const KittiLengthResult& l : r.per_length) {
    EXPECT_FALSE(l.translation_error_percent.has_value());
  }
}

TEST(KittiMetric, RealSixteenFrameSequenceReportsNoSegment) {
  const std::string path = std::string(PLUCKER_SHARED_DATA_DIR) + "/kitti-odometry-00/poses/00.txt";
  if (!std::ifstream(path)) GTEST_SKIP() << "shared data absent: " << path;
  const io::Trajectory gt = io::ReadTrajectory(path);
  ASSERT_EQ(gt.poses.size(), 16u);
  const KittiResult r = ComputeKittiMetric(gt.poses, gt.poses);
  EXPECT_FALSE(r.has_segments());
  EXPECT_GT(r.path_length, 5.0);
  EXPECT_LT(r.path_length, 100.0);
}

TEST(KittiMetric, RejectsMismatchedSizesAndBadOptions) {
  EXPECT_THROW(ComputeKittiMetric(StraightLine(10, 1), StraightLine(11, 1)), std::invalid_argument);
  EXPECT_THROW(ComputeKittiMetric({}, {}), std::invalid_argument);
  KittiOptions bad;
  bad.step_size = 0;
  EXPECT_THROW(ComputeKittiMetric(StraightLine(10, 1), StraightLine(10, 1), bad),
               std::invalid_argument);
}

TEST(KittiMetric, DevkitRotationAngleIsClamped) {
  EXPECT_EQ(DevkitRotationAngle(Eigen::Matrix3d::Identity() * 1.0000001), 0.0);
  EXPECT_NEAR(DevkitRotationAngle(-Eigen::Matrix3d::Identity()), M_PI, 1e-12);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  EXPECT_NEAR(DevkitRotationAngle(R), 0.3, 1e-12);
}

}  // namespace
}  // namespace eval
}  // namespace plucker
