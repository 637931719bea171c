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

TEST(DeskewTest, BadInputLeavesPointsUntouched) {
  std::vector<Eigen::Vector3d> pts = {Eigen::Vector3d(1, 2, 3)};
  EXPECT_FALSE(DeskewPoints(SE3d(), 0.1, {}, &pts));
  EXPECT_FALSE(DeskewPoints(SE3d(), 0.0, {0.0}, &pts));
  EXPECT_EQ(pts[0], Eigen::Vector3d(1, 2, 3));
}

}  // namespace
}  // namespace lidar
}  // namespace plucker
