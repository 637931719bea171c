#include "plucker/lidar/deskew.h"

#include <gtest/gtest.h>

namespace plucker {
namespace lidar {
namespace {

TEST(DeskewTest, PointsMoveToTheScanStartFrame) {
  // The sensor moves 1 m along x and turns 10 deg about z during one 0.1 s sweep. A static world
  // point seen at time t is p_t = T_start_t^-1 p_start; deskewing must give p_start back.
  const SE3d motion(ExpSO3<double>(Eigen::Vector3d(0, 0, 10 * M_PI / 180)),
                    Eigen::Vector3d(1, 0, 0));
  const Eigen::Vector3d p_start(10, 3, -1);
  std::vector<Eigen::Vector3d> pts;
  std::vector<double> times;
  for (int i = 0; i <= 10; ++i) {
    const double t = 0.01 * i;
    times.push_back(t);
    pts.push_back(InterpolateMotion(motion, t / 0.1).Inverse() * p_start);
  }
  ASSERT_TRUE(DeskewPoints(motion, 0.1, times, &pts));
  for (const auto& p : pts) EXPECT_LT((p - p_start).norm(), 1e-12);
  // The end of the interpolation is the full motion.
  const SE3d end = InterpolateMotion(motion, 1.0);
  EXPECT_LT((end.translation() - motion.translation()).norm(), 1e-12);
  EXPECT_LT(end.rotation().angularDistance(motion.rotation()), 1e-12);
}

// An independent reference, written out by hand: over the sweep the sensor turns 10 deg about z
// and moves 1 m along x. Halfway (fraction 0.5, t = 0.05 s of 0.1 s) the pose is 5 deg of yaw and
// 0.5 m along x: R = [cos 5, -sin 5, 0; sin 5, cos 5, 0; 0, 0, 1], cos 5 deg = 0.9961946980917455,
// sin 5 deg = 0.08715574274765817. A point seen then at (10, 0, 2) in the sensor frame is, in the
// scan-start frame, R (10, 0, 2) + (0.5, 0, 0) = (10.461946980917455, 0.8715574274765816, 2).
TEST(DeskewTest, HalfwayPoseMatchesAHandComputedReference) {
  const SE3d T_start_end(ExpSO3<double>(Eigen::Vector3d(0, 0, 10 * M_PI / 180)),
                         Eigen::Vector3d(1, 0, 0));
  const SE3d T_start_half = InterpolateMotion(T_start_end, 0.5);
  Eigen::Matrix3d R_expected;
  R_expected << 0.9961946980917455, -0.08715574274765817, 0, 0.08715574274765817,
      0.9961946980917455, 0, 0, 0, 1;
  EXPECT_LT((T_start_half.RotationMatrix() - R_expected).norm(), 1e-15);
  EXPECT_LT((T_start_half.translation() - Eigen::Vector3d(0.5, 0, 0)).norm(), 1e-15);
  std::vector<Eigen::Vector3d> pts = {Eigen::Vector3d(10, 0, 2), Eigen::Vector3d(10, 0, 2)};
  ASSERT_TRUE(DeskewPoints(T_start_end, 0.1, {0.05, 0.0}, &pts));
  EXPECT_LT((pts[0] - Eigen::Vector3d(10.461946980917455, 0.8715574274765816, 2)).norm(), 1e-13);
  EXPECT_LT((pts[1] - Eigen::Vector3d(10, 0, 2)).norm(), 1e-15);  // scan start: unchanged
}

TEST(DeskewTest, BadInputLeavesPointsUntouched) {
  std::vector<Eigen::Vector3d> pts = {Eigen::Vector3d(1, 2, 3)};
  EXPECT_FALSE(DeskewPoints(SE3d(), 0.1, {}, &pts));
  EXPECT_FALSE(DeskewPoints(SE3d(), 0.0, {0.0}, &pts));
  EXPECT_EQ(pts[0], Eigen::Vector3d(1, 2, 3));
}

}  // namespace
}  // namespace lidar
}  // namespace plucker
