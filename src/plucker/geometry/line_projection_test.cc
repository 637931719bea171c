#include "plucker/geometry/line_projection.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <limits>

#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace {

using verify::Rng;

PinholeIntrinsics TestIntrinsics() { return {520.0, 510.0, 321.0, 243.0}; }

TEST(LineProjection, LineIntrinsicsIsDetKTimesInverseTranspose) {
  const PinholeIntrinsics K = TestIntrinsics();
  const Eigen::Matrix3d expected = K.K().determinant() * K.K().inverse().transpose();
  EXPECT_LT((LineIntrinsics(K) - expected).norm(), 1e-9 * expected.norm());
}

TEST(LineProjection, ProjectedPointsLieOnTheImageLine) {
  const PinholeIntrinsics K = TestIntrinsics();
  Rng rng(1);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d p1(verify::Uniform(rng, -2, 2), verify::Uniform(rng, -2, 2),
                             verify::Uniform(rng, 1, 8));
    const Eigen::Vector3d p2(verify::Uniform(rng, -2, 2), verify::Uniform(rng, -2, 2),
                             verify::Uniform(rng, 1, 8));
    const Line6d L_c = LineFromPoints(p1, p2);
    const Eigen::Vector3d l_n = ProjectLineNormalized(L_c);
    Eigen::Matrix<double, 3, 6> J;
    const Eigen::Vector3d l_px = ProjectLinePixels(K, L_c, &J);
    EXPECT_LT((J.leftCols<3>() - LineIntrinsics(K)).norm(), 1e-12);
    EXPECT_EQ(J.rightCols<3>(), Eigen::Matrix3d::Zero());
    EXPECT_LT((ProjectLinePixels<double>(LineIntrinsics(K), L_c) - l_px).norm(), 1e-9);
    // Any point of the 3D line, in normalized coordinates and in pixels.
    const Eigen::Vector3d p = p1 + verify::Uniform(rng, -0.5, 1.5) * (p2 - p1);
    if (p.z() < 0.1) continue;
    const Eigen::Vector2d xn = p.head<2>() / p.z();
    EXPECT_NEAR(l_n.dot(xn.homogeneous()), 0.0, 1e-12 * l_n.norm());
    const Eigen::Vector2d uv = K.ToPixel(xn);
    EXPECT_NEAR(l_px.dot(uv.homogeneous()) / l_px.head<2>().norm(), 0.0, 1e-9);
  }
}

TEST(LineProjection, ResidualIsSignedPixelDistance) {
  // The image line v = 100 (l = (0, 1, -100)), scaled arbitrarily.
  const Eigen::Vector3d l = 7.0 * Eigen::Vector3d(0, 1, -100);
  Eigen::Matrix<double, 2, 3> J;
  const auto r = EndpointLineResidual(l, Eigen::Vector2d(10, 103), Eigen::Vector2d(500, 98), &J);
  ASSERT_TRUE(r);
  EXPECT_NEAR((*r)(0), 3.0, 1e-12);
  EXPECT_NEAR((*r)(1), -2.0, 1e-12);
  // Scale invariance of the residual.
  EXPECT_LT(
      (*EndpointLineResidual(-0.01 * l, Eigen::Vector2d(10, 103), Eigen::Vector2d(500, 98)) + *r)
          .norm(),
      1e-12);
  // Endpoints on the line: zero.
  const auto zero = EndpointLineResidual(l, Eigen::Vector2d(0, 100), Eigen::Vector2d(50, 100));
  EXPECT_LT(zero->norm(), 1e-12);
}

TEST(LineProjection, GuardRefusesLinesWithoutAnImageLine) {
  const PinholeIntrinsics K = TestIntrinsics();
  const Eigen::Vector2d s(100, 100), e(200, 150);
  Eigen::Matrix<double, 2, 3> J = Eigen::Matrix<double, 2, 3>::Constant(42.0);
  // Direction along the optical axis through the centre: n_c = 0, projects to a point.
  const Line6d axis = LineFromPoints<double>(Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, 3));
  EXPECT_TRUE(LineThroughCameraCentre<double>(axis));
  EXPECT_FALSE(EndpointLineResidual(ProjectLinePixels(K, axis), s, e, &J));
  // In the principal plane z_c = 0: l ~ (0, 0, 1), the line at infinity.
  const Line6d in_plane =
      LineFromPoints<double>(Eigen::Vector3d(1, 2, 0), Eigen::Vector3d(-1, 3, 0));
  EXPECT_FALSE(LineThroughCameraCentre<double>(in_plane));
  EXPECT_FALSE(EndpointLineResidual(ProjectLinePixels(K, in_plane), s, e, &J));
  EXPECT_FALSE(EndpointLineResidual(Eigen::Vector3d(1e-7, 0, 1), s, e, &J));
  EXPECT_EQ(J, (Eigen::Matrix<double, 2, 3>::Constant(42.0)));  // untouched on failure
  // Non-finite input.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(EndpointLineResidual(Eigen::Vector3d(nan, 1, 0), s, e));
  EXPECT_FALSE(EndpointLineResidual(Eigen::Vector3d(1, 1, 0), Eigen::Vector2d(nan, 0), e));
  EXPECT_FALSE(EndpointLineResidual(Eigen::Vector3d(1, 1, 0), s,
                                    Eigen::Vector2d(0, std::numeric_limits<double>::infinity())));
  // Just inside the guard: a regular, finite result.
  EXPECT_TRUE(EndpointLineResidual(Eigen::Vector3d(1e-5, 0, 1), s, e));
}

TEST(LineProjection, LineParallelToOpticalAxisPassesThroughPrincipalPoint) {
  const PinholeIntrinsics K = TestIntrinsics();
  const Line6d L_c =
      LineFromPoints<double>(Eigen::Vector3d(0.5, -0.3, 1), Eigen::Vector3d(0.5, -0.3, 6));
  EXPECT_FALSE(LineThroughCameraCentre<double>(L_c));
  const Eigen::Vector3d l = ProjectLinePixels(K, L_c);
  const auto r = EndpointLineResidual(l, Eigen::Vector2d(K.cx, K.cy), Eigen::Vector2d(0, 0));
  ASSERT_TRUE(r);
  EXPECT_NEAR((*r)(0), 0.0, 1e-9);
}

}  // namespace
}  // namespace plucker
