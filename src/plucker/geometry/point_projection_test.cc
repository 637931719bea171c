#include "plucker/geometry/point_projection.h"
#include "plucker/geometry/geometry_test_utils.h"

#include <gtest/gtest.h>

#include <limits>

#include "plucker/verify/checks.h"

namespace plucker {
namespace {

using testing_utils::LookAt;
using testing_utils::TestK;

TEST(PointProjection, KnownValues) {
  const auto uv = ProjectCameraPoint(TestK(), Eigen::Vector3d(1, -2, 4));
  ASSERT_TRUE(uv.has_value());
  EXPECT_DOUBLE_EQ(uv->x(), 320 + 500 * 0.25);
  EXPECT_DOUBLE_EQ(uv->y(), 240 - 480 * 0.5);
  // A camera at (0, 0, -4) rotated by pi/2 about z: world x maps to camera -y.
  const SE3d T_w_c(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ())),
                   Eigen::Vector3d(0, 0, -4));
  const auto uv_w = ProjectPoint(TestK(), T_w_c, Eigen::Vector3d(2, 0, 0));
  ASSERT_TRUE(uv_w.has_value());
  EXPECT_NEAR(uv_w->x(), 320, 1e-12);
  EXPECT_NEAR(uv_w->y(), 240 - 480 * 0.5, 1e-12);
}

TEST(PointProjection, TemplateMatchesDouble) {
  const SE3d T_w_c(Eigen::Quaterniond(0.3, -0.2, 0.5, 0.7), Eigen::Vector3d(1, 2, -3));
  const Eigen::Vector3d p_w = T_w_c * Eigen::Vector3d(0.3, 0.4, 5.0);
  Eigen::Vector2d uv_t;
  ASSERT_TRUE(ProjectPointT<double>(TestK(), T_w_c, p_w, &uv_t));
  EXPECT_LT((uv_t - *ProjectPoint(TestK(), T_w_c, p_w)).norm(), 1e-12);
}

TEST(PointProjection, RejectsPointsNotInFront) {
  const PinholeIntrinsics K = TestK();
  EXPECT_FALSE(ProjectCameraPoint(K, Eigen::Vector3d(0, 0, 0)).has_value());
  EXPECT_FALSE(ProjectCameraPoint(K, Eigen::Vector3d(1, 1, -2)).has_value());
  EXPECT_FALSE(ProjectCameraPoint(K, Eigen::Vector3d(1, 1, 1e-7)).has_value());
  EXPECT_TRUE(ProjectCameraPoint(K, Eigen::Vector3d(1, 1, 2e-6)).has_value());
  EXPECT_FALSE(ProjectCameraPoint(K, Eigen::Vector3d(1, 1, 0.5), nullptr, 0.5).has_value());
  Eigen::Vector2d uv(-1, -1);
  EXPECT_FALSE(ProjectCameraPointT<double>(K, Eigen::Vector3d(1, 1, -2), &uv));
  EXPECT_EQ(uv, Eigen::Vector2d(-1, -1));  // untouched
}

TEST(PointProjection, RejectsNonFiniteInput) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const PinholeIntrinsics K = TestK();
  EXPECT_FALSE(ProjectCameraPoint(K, Eigen::Vector3d(nan, 0, 1)).has_value());
  EXPECT_FALSE(ProjectCameraPoint(K, Eigen::Vector3d(0, 0, inf)).has_value());
  EXPECT_FALSE(ProjectPoint(K, SE3d(), Eigen::Vector3d(0, inf, 3)).has_value());
  EXPECT_FALSE(ProjectPoint(K, SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(nan, 0, 0)),
                            Eigen::Vector3d(0, 0, 3))
                   .has_value());
  PinholeIntrinsics bad = K;
  bad.fx = nan;
  EXPECT_FALSE(ProjectCameraPoint(bad, Eigen::Vector3d(0, 0, 1)).has_value());
}

TEST(PointProjection, JacobianChecksPass) {
  verify::JacobianCheckOptions options;
  options.samples = 1000;
  const verify::JacobianCheckRun run =
      verify::RunJacobianChecks(verify::ProjectionJacobianChecks(), "", 3, options);
  EXPECT_TRUE(run.ok()) << run.error;
  for (const verify::JacobianCheckStats& s : run.stats) EXPECT_EQ(s.skipped, 0) << s.name;
}

}  // namespace
}  // namespace plucker
