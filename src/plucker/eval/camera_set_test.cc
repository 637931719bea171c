#include "plucker/eval/camera_set.h"

#include <gtest/gtest.h>

#include <cmath>

namespace plucker {
namespace eval {
namespace {

std::vector<SE3d> Cameras() {
  std::vector<SE3d> c;
  for (int i = 0; i < 6; ++i) {
    const double a = 0.3 * i;
    c.emplace_back(Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY())),
                   Eigen::Vector3d(3 * std::sin(a), 0.2 * i, -3 * std::cos(a)));
  }
  return c;
}

// est = S^-1 gt: a similarity of the ground truth, with one camera missing.
TEST(CameraSet, SimilarityAndMissingCamerasGiveZeroError) {
  const std::vector<SE3d> gt = Cameras();
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const double s = 0.37;
  const Eigen::Vector3d t(1, -2, 0.5);
  std::vector<std::optional<SE3d>> est;
  for (const SE3d& T : gt) est.push_back(SE3d(q * T.rotation(), s * (q * T.translation()) + t));
  est[3].reset();
  const CameraSetErrors e = CompareCameraSets(est, gt);
  ASSERT_TRUE(e.ok) << e.message;
  EXPECT_EQ(e.registered, 5);
  ASSERT_EQ(e.missing, std::vector<int>{3});
  EXPECT_NEAR(e.scale, 1.0 / s, 1e-9);
  EXPECT_LT(e.max_centre, 1e-9);
  EXPECT_LT(e.max_rotation_deg, 1e-6);
  EXPECT_LT(e.max_rotation_centres_deg, 1e-6);
}

TEST(CameraSet, ARotatedCameraShowsItsRotationError) {
  const std::vector<SE3d> gt = Cameras();
  std::vector<std::optional<SE3d>> est(gt.begin(), gt.end());
  const double angle_deg = 0.1;
  est[2] = SE3d(gt[2].rotation() * Eigen::Quaterniond(Eigen::AngleAxisd(angle_deg * M_PI / 180,
                                                                        Eigen::Vector3d::UnitZ())),
                gt[2].translation());
  const CameraSetErrors e = CompareCameraSets(est, gt);
  ASSERT_TRUE(e.ok);
  EXPECT_LT(e.max_centre, 1e-12);
  // The orientation fit spreads the error over the cameras; the centres' alignment does not.
  EXPECT_NEAR(e.max_rotation_centres_deg, angle_deg, 1e-9);
  EXPECT_NEAR(e.rotation_error_deg[2], angle_deg * 5.0 / 6.0, 1e-3);
}

TEST(CameraSet, RefusesTooFewCamerasAndSizeMismatch) {
  const std::vector<SE3d> gt = Cameras();
  std::vector<std::optional<SE3d>> est(gt.size());
  est[0] = gt[0];
  est[1] = gt[1];
  CameraSetErrors e = CompareCameraSets(est, gt);
  EXPECT_FALSE(e.ok);
  EXPECT_NE(e.message.find("at least 3"), std::string::npos) << e.message;
  est.pop_back();
  e = CompareCameraSets(est, gt);
  EXPECT_FALSE(e.ok);
  EXPECT_NE(e.message.find("the ground truth 6"), std::string::npos) << e.message;
}

}  // namespace
}  // namespace eval
}  // namespace plucker
