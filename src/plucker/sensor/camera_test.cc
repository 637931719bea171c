#include "plucker/sensor/camera.h"

#include <gtest/gtest.h>

#include <limits>

#include "plucker/sensor/camera_test_utils.h"

namespace plucker {
namespace sensor {
namespace {

using sensor::testing::EurocCam0;
using sensor::testing::TumViCam0;

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

// Every pixel of a grid over the fisheye image inside the 180 deg field of view goes to a
// bearing and back to 1e-9 px (and through normalized coordinates, away from 90 deg); the
// pixels beyond it (the image corners of this 195 deg lens) are refused in both directions.
TEST(Camera, EquidistantRoundTripAndRefusal) {
  const Camera c = TumViCam0();
  ASSERT_TRUE(c.IsValid()) << c.Problem();
  EXPECT_FALSE(c.IsPinhole());
  const double edge = c.equidistant.ThetaD(M_PI / 2);  // distorted radius at 90 deg
  int inside = 0, refused = 0;
  double worst = 0, worst_normalized = 0;
  for (int v = 0; v < c.height; v += 8) {
    for (int u = 0; u < c.width; u += 8) {
      const Eigen::Vector2d uv(u, v);
      const auto bearing = c.PixelToBearing(uv);
      if (c.PixelToDistortedNormalized(uv).norm() > edge) {
        EXPECT_FALSE(bearing.has_value()) << u << " " << v;
        EXPECT_FALSE(c.PixelToNormalized(uv).has_value());
        ++refused;
        continue;
      }
      ASSERT_TRUE(bearing.has_value()) << u << " " << v;
      EXPECT_NEAR(bearing->norm(), 1.0, 1e-15);
      if (bearing->z() > 1e-9) {
        const auto back = c.Project(2.5 * *bearing);
        ASSERT_TRUE(back.has_value()) << u << " " << v;
        worst = std::max(worst, (*back - uv).norm());
      }
      if (bearing->z() > 1e-3) {
        const auto xn = c.PixelToNormalized(uv);
        ASSERT_TRUE(xn.has_value());
        worst_normalized = std::max(worst_normalized, (c.NormalizedToPixel(*xn) - uv).norm());
        EXPECT_LT((*c.DistortPixel(*c.UndistortPixel(uv)) - uv).norm(), 1e-9);
      }
      ++inside;
    }
  }
  EXPECT_GT(inside, 3000);
  EXPECT_GT(refused, 100);
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(worst_normalized, 1e-9);
  // Behind the camera, at its centre, non-finite: no pixel.
  EXPECT_FALSE(c.Project(Eigen::Vector3d(1, 0, -0.1)).has_value());
  EXPECT_FALSE(c.Project(Eigen::Vector3d::Zero()).has_value());
  EXPECT_EQ(*c.Project(Eigen::Vector3d(0, 0, 3)), Eigen::Vector2d(c.K.cx, c.K.cy));
  // The undistorted twin is the radial-tangential pinhole with the same K.
  const Camera ideal = c.Undistorted();
  EXPECT_TRUE(ideal.IsPinhole());
  EXPECT_EQ(ideal.model, CameraModel::kRadialTangential);
  Camera bad = c;
  bad.equidistant.k4 = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(bad.Problem().find("equidistant"), std::string::npos) << bad.Problem();
  EXPECT_STREQ(CameraModelName(c.model), "equidistant");
  EXPECT_STREQ(CameraModelName(ideal.model), "radtan");
}

// ProjectWithJacobian gives Project's value bit for bit (both models), and radtan's bearing is
// its normalized point's direction.
TEST(Camera, ProjectWithJacobianMatchesProject) {
  for (const Camera& c : {EurocCam0(), TumViCam0(), EurocCam0().Undistorted()}) {
    for (const Eigen::Vector3d& p :
         {Eigen::Vector3d(0, 0, 2), Eigen::Vector3d(0.3, -0.2, 1.5), Eigen::Vector3d(-2, 1, 0.8)}) {
      Eigen::Matrix<double, 2, 3> J;
      const auto a = c.Project(p);
      const auto b = c.ProjectWithJacobian(p, &J);
      ASSERT_EQ(a.has_value(), b.has_value());
      if (a) {
        EXPECT_EQ(*a, *b);
      }
    }
    EXPECT_FALSE(c.ProjectWithJacobian(Eigen::Vector3d(0, 0, -1), nullptr).has_value());
  }
  const Camera c = EurocCam0();
  const Eigen::Vector2d uv(100, 400);
  const Eigen::Vector2d xn = *c.PixelToNormalized(uv);
  EXPECT_LT((*c.PixelToBearing(uv) - Eigen::Vector3d(xn.x(), xn.y(), 1).normalized()).norm(),
            1e-15);
}

}  // namespace
}  // namespace sensor
}  // namespace plucker
