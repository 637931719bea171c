#include "plucker/lidar/odometry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

#include "plucker/io/lidar_sequence.h"
#include "plucker/io/trajectory_io.h"
#include "plucker/lidar/scan_test_utils.h"

namespace plucker {
namespace lidar {
namespace {

double AngleDeg(const Eigen::Quaterniond& q) { return LogSO3(q).norm() * 180.0 / M_PI; }

// Ground-truth trajectory: forward 1 m per frame with a slow yaw (1 deg/frame) and small roll.
SE3d TruePose(int i) {
  const double yaw = i * M_PI / 180.0;
  const Eigen::Quaterniond q = ExpSO3<double>(Eigen::Vector3d(0.002 * std::sin(i), 0.0, yaw));
  return SE3d(q, Eigen::Vector3d(1.0 * i, 0.05 * i * i, 0.0));
}

TEST(LidarOdometryTest, RecoversKnownMotionOnSyntheticUrbanScans) {
  const test::Scene scene = test::UrbanScene();
  test::ScanPattern pattern;
  pattern.noise = 0.01;
  LidarOdometryOptions options;
  LidarOdometry odometry(options);
  const int frames = 8;
  for (int i = 0; i < frames; ++i) {
    const SE3d T_w_s = TruePose(0).Inverse() * TruePose(i);
    const FrameResult r = odometry.ProcessScan(test::MakeScan(scene, TruePose(i), pattern, i + 1));
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_GT(r.features.edges, 10);
    EXPECT_GT(r.features.planes, 100);
    if (i > 0) {
      EXPECT_GT(r.plane_correspondences, 100);
      EXPECT_FALSE(r.degeneracy.degenerate) << r.degeneracy.eigenvalues.transpose();
    }
    const SE3d E = T_w_s.Inverse() * r.T_w_s;
    EXPECT_LT(E.translation().norm(), 0.02) << "frame " << i;
    EXPECT_LT(AngleDeg(E.rotation()), 0.05) << "frame " << i;
  }
}

TEST(LidarOdometryTest, SkippedFrameGetsConstantVelocityPrediction) {
  const test::Scene scene = test::UrbanScene();
  test::ScanPattern pattern;
  LidarOdometry odometry;
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(odometry.ProcessScan(test::MakeScan(scene, TruePose(i), pattern)).ok);
  const FrameResult skipped = odometry.SkipFrame("file.bin: truncated");
  EXPECT_FALSE(skipped.ok);
  EXPECT_EQ(skipped.error, "file.bin: truncated");
  const auto& p = odometry.poses();
  ASSERT_EQ(p.size(), 4u);
  const SE3d expected = p[2] * (p[1].Inverse() * p[2]);
  EXPECT_LT((skipped.T_w_s.translation() - expected.translation()).norm(), 1e-9);
  // An empty scan is skipped, not a crash.
  const FrameResult empty = odometry.ProcessScan(LidarScan());
  EXPECT_FALSE(empty.ok);
  EXPECT_FALSE(empty.error.empty());
  EXPECT_EQ(odometry.poses().size(), 5u);
}

TEST(LidarOdometryTest, CorridorIsDetectedDegenerateAndStableAlongItsAxis) {
  const test::Scene scene = test::CorridorScene();
  test::ScanPattern pattern;
  pattern.rings = 16;
  pattern.min_elevation_deg = -15;
  pattern.max_elevation_deg = 15;
  pattern.noise = 0.005;
  LidarOdometry odometry;
  // The sensor truly moves 0.5 m per frame along the corridor axis, which the scans cannot show.
  for (int i = 0; i < 6; ++i) {
    const SE3d T_true(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.5 * i, 0.1, 0.0));
    const std::vector<SE3d> before = odometry.poses();
    const FrameResult r = odometry.ProcessScan(test::MakeScan(scene, T_true, pattern, i + 1));
    ASSERT_TRUE(r.ok) << r.error;
    if (i == 0) continue;
    EXPECT_TRUE(r.degeneracy.degenerate) << r.degeneracy.eigenvalues.transpose();
    EXPECT_GE(r.degeneracy.num_degenerate_directions, 1);
    // The weakest direction is the translation along x.
    const Vector6d v = r.degeneracy.eigenvectors.col(0);
    EXPECT_GT(std::abs(v(3)), 0.9) << v.transpose();
    // Along x the estimate keeps the (constant-velocity) prediction: no drift from noise.
    SE3d predicted = before.back();
    if (before.size() >= 2) predicted = before.back() * (before[before.size() - 2].Inverse() * before.back());
    EXPECT_NEAR(r.T_w_s.translation().x(), predicted.translation().x(), 1e-3);
    // The well-constrained directions stay right (the first frame fixes y = 0.1 as origin).
    EXPECT_NEAR(r.T_w_s.translation().y(), 0.0, 0.01);
    EXPECT_NEAR(r.T_w_s.translation().z(), 0.0, 0.01);
    EXPECT_LT(AngleDeg(r.T_w_s.rotation()), 0.1);
  }
}

// End-to-end on the real KITTI extract: per-frame relative pose error against poses/00.txt
// (cam0 frame, compared through Tr). A correctness test, not a timing one.
TEST(LidarOdometryTest, KittiExtractMeetsPerFrameAccuracy) {
  const std::string root = std::string(PLUCKER_SHARED_DATA_DIR) + "/kitti-odometry-00";
  if (!std::filesystem::exists(root + "/sequences/00/velodyne")) {
    GTEST_SKIP() << "KITTI extract not found at " << root;
  }
  const io::LidarSequence seq = io::LidarSequence::Open(root, "00");
  ASSERT_TRUE(seq.T_cam0_velo().has_value());
  const std::vector<SE3d> gt = io::ReadTrajectory(root + "/poses/00.txt").poses;
  ASSERT_GE(gt.size(), seq.size());
  LidarOdometry odometry;
  for (std::size_t i = 0; i < seq.size(); ++i) {
    LidarScan scan;
    std::string error;
    ASSERT_TRUE(seq.Read(i, &scan, &error)) << error;
    const FrameResult r = odometry.ProcessScan(std::move(scan));
    ASSERT_TRUE(r.ok) << "frame " << i << ": " << r.error;
  }
  const SE3d Tr = *seq.T_cam0_velo();
  std::vector<double> dt, dr;
  const auto& est = odometry.poses();
  for (std::size_t i = 0; i + 1 < seq.size(); ++i) {
    const SE3d rel_est = Tr * (est[i].Inverse() * est[i + 1]) * Tr.Inverse();
    const SE3d rel_gt = gt[i].Inverse() * gt[i + 1];
    const SE3d E = rel_gt.Inverse() * rel_est;
    dt.push_back(E.translation().norm());
    dr.push_back(AngleDeg(E.rotation()));
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  };
  const double med_t = median(dt), med_r = median(dr);
  RecordProperty("median_rpe_cm", std::to_string(100 * med_t));
  RecordProperty("median_rpe_deg", std::to_string(med_r));
  std::printf("KITTI 00 frames 0-%zu: median RPE %.2f cm, %.4f deg\n", seq.size() - 1, 100 * med_t,
              med_r);
  EXPECT_LT(med_t, 0.02);
  EXPECT_LT(med_r, 0.05);
}

}  // namespace
}  // namespace lidar
}  // namespace plucker
