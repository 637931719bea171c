#include "plucker/sensor/camera.h"

#include <gtest/gtest.h>

#include <limits>

#include "plucker/sensor/camera_test_utils.h"

namespace plucker {
namespace sensor {
namespace {

using sensor::testing::EurocCam0;

TEST(Camera, ValidityNamesTheProblem) {
  EXPECT_TRUE(EurocCam0().IsValid());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Camera c = EurocCam0();
  c.K.fx = 0;
  EXPECT_NE(c.Problem().find("fx"), std::string::npos) << c.Problem();
  c = EurocCam0();
  c.K.fy = -3;
  EXPECT_NE(c.Problem().find("fy"), std::string::npos) << c.Problem();
  c = EurocCam0();
  c.K.fx = nan;
  EXPECT_FALSE(c.IsValid());
  c = EurocCam0();
  c.K.cy = std::numeric_limits<double>::infinity();
  EXPECT_NE(c.Problem().find("principal point"), std::string::npos) << c.Problem();
  c = EurocCam0();
  c.distortion.k2 = nan;
  EXPECT_NE(c.Problem().find("distortion"), std::string::npos) << c.Problem();
  c = EurocCam0();
  c.height = 0;
  EXPECT_NE(c.Problem().find("image size"), std::string::npos) << c.Problem();
}

// Every pixel of a grid over the EuRoC image goes to normalized coordinates and back.
TEST(Camera, PixelNormalizedRoundTripOverTheImage) {
  const Camera c = EurocCam0();
  int checked = 0;
  double max_error = 0;
  for (int v = 0; v < c.height; v += 16) {
    for (int u = 0; u < c.width; u += 16) {
      const Eigen::Vector2d uv(u, v);
      const auto xn = c.PixelToNormalized(uv);
      ASSERT_TRUE(xn.has_value()) << u << " " << v;
      max_error = std::max(max_error, (c.NormalizedToPixel(*xn) - uv).norm());
      const auto ideal = c.UndistortPixel(uv);
      ASSERT_TRUE(ideal.has_value());
      EXPECT_LT((c.K.ToPixel<double>(*xn) - *ideal).norm(), 1e-9);
      EXPECT_LT((*c.DistortPixel(*ideal) - uv).norm(), 1e-6);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 47 * 30);
  EXPECT_LT(max_error, 1e-6);
  // The corner moves by tens of pixels under this lens: the conversion is not a no-op.
  EXPECT_GT((*c.UndistortPixel(Eigen::Vector2d(0, 0)) - Eigen::Vector2d(0, 0)).norm(), 20.0);
}

TEST(Camera, PinholeIsKOnly) {
  Camera c = EurocCam0().Undistorted();
  EXPECT_TRUE(c.IsPinhole());
  EXPECT_FALSE(EurocCam0().IsPinhole());
  const Eigen::Vector2d uv(3.25, 470.5);
  EXPECT_EQ(*c.UndistortPixel(uv), uv);
  EXPECT_EQ(c.PixelToDistortedNormalized(uv), *c.PixelToNormalized(uv));
  EXPECT_LT((c.DistortedNormalizedToPixel(c.PixelToDistortedNormalized(uv)) - uv).norm(), 1e-12);
}

TEST(Camera, ProjectAndInImage) {
  const Camera c = EurocCam0();
  EXPECT_FALSE(c.Project(Eigen::Vector3d(0, 0, -1)).has_value());
  EXPECT_FALSE(c.Project(Eigen::Vector3d(0, 0, 0)).has_value());
  EXPECT_FALSE(c.Project(Eigen::Vector3d(std::numeric_limits<double>::quiet_NaN(), 0, 1)));
  const auto centre = c.Project(Eigen::Vector3d(0, 0, 2));
  ASSERT_TRUE(centre.has_value());
  EXPECT_LT((*centre - Eigen::Vector2d(c.K.cx, c.K.cy)).norm(), 1e-12);
  EXPECT_TRUE(c.InImage(*centre));
  EXPECT_TRUE(c.InImage(Eigen::Vector2d(751.4, 479.4)));
  EXPECT_FALSE(c.InImage(Eigen::Vector2d(752, 100)));
  EXPECT_FALSE(c.InImage(Eigen::Vector2d(-0.6, 100)));
  EXPECT_FALSE(c.PixelToNormalized(Eigen::Vector2d(std::numeric_limits<double>::infinity(), 0)));
}

}  // namespace
}  // namespace sensor
}  // namespace plucker
