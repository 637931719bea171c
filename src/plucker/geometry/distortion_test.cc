#include "plucker/geometry/distortion.h"

#include <gtest/gtest.h>

#include <limits>

namespace plucker {
namespace {

// KITTI raw cam 0 calibration (1392 x 512 image).
PinholeIntrinsics KittiK() { return {984.2439, 980.8141, 690.0, 233.1966}; }
RadTanDistortion KittiD() {
  RadTanDistortion D;
  D.k1 = -0.3745594;
  D.k2 = 0.2049385;
  D.p1 = 1.110145e-3;
  D.p2 = 1.379375e-3;
  D.k3 = -0.07084798;
  return D;
}
// Strong barrel distortion of a wide-angle lens (normalized radius up to 0.8 in the image; the
// distorted radius peaks near 0.95, beyond which Undistort must fail).
RadTanDistortion StrongD() {
  RadTanDistortion D;
  D.k1 = -0.42;
  D.k2 = 0.18;
  D.p1 = 4e-3;
  D.p2 = -3e-3;
  D.k3 = -0.03;
  return D;
}

void ExpectRoundTripsOnGrid(const PinholeIntrinsics& K, const RadTanDistortion& D, double width,
                            double height) {
  int n = 0;
  for (double u = 0; u <= width; u += width / 40) {
    for (double v = 0; v <= height; v += height / 20) {
      const Eigen::Vector2d uv_d(u, v);
      // Distorted pixel -> ideal -> distorted.
      const auto uv_i = UndistortPixel(K, D, uv_d);
      ASSERT_TRUE(uv_i.has_value()) << u << " " << v;
      const auto back = DistortPixel(K, D, *uv_i);
      ASSERT_TRUE(back.has_value());
      EXPECT_LT((*back - uv_d).norm(), 1e-8) << u << " " << v;
      // Ideal pixel -> distorted -> ideal.
      const auto d2 = DistortPixel(K, D, uv_d);
      ASSERT_TRUE(d2.has_value());
      const auto i2 = UndistortPixel(K, D, *d2);
      ASSERT_TRUE(i2.has_value()) << u << " " << v;
      EXPECT_LT((*i2 - uv_d).norm(), 1e-8) << u << " " << v;
      ++n;
    }
  }
  EXPECT_GT(n, 800);
}

TEST(Distortion, RoundTripKittiGrid) { ExpectRoundTripsOnGrid(KittiK(), KittiD(), 1392, 512); }

TEST(Distortion, RoundTripStrongGrid) {
  ExpectRoundTripsOnGrid(PinholeIntrinsics{500, 500, 320, 240}, StrongD(), 640, 480);
}

TEST(Distortion, ZeroDistortionIsIdentity) {
  const Eigen::Vector2d x(0.3, -0.7);
  Eigen::Matrix2d J;
  EXPECT_EQ(Distort(RadTanDistortion(), x, &J), x);
  EXPECT_TRUE(J.isIdentity(0.0));
  EXPECT_EQ(*Undistort(RadTanDistortion(), x), x);
}

TEST(Distortion, JacobianMatchesCentralDifferences) {
  for (const RadTanDistortion& D : {KittiD(), StrongD()}) {
    for (const Eigen::Vector2d& x :
         {Eigen::Vector2d(0, 0), Eigen::Vector2d(0.3, -0.2), Eigen::Vector2d(-0.6, 0.4)}) {
      Eigen::Matrix2d J;
      Distort(D, x, &J);
      Eigen::Matrix2d Jn;
      const double h = 1e-6;
      for (int k = 0; k < 2; ++k) {
        Eigen::Vector2d e = Eigen::Vector2d::Zero();
        e(k) = h;
        Jn.col(k) = (Distort(D, x + e) - Distort(D, x - e)) / (2 * h);
      }
      EXPECT_LT((J - Jn).norm(), 1e-8);
    }
  }
}

TEST(Distortion, OutsideValidRegionReturnsNullopt) {
  // Pure barrel k1 = -0.45: r_d(r) = r - 0.45 r^3 peaks at r = 0.861 with r_d = 0.574; beyond
  // that no ideal point maps there.
  RadTanDistortion D;
  D.k1 = -0.45;
  EXPECT_FALSE(Undistort(D, Eigen::Vector2d(0.6, 0.0)).has_value());
  EXPECT_FALSE(Undistort(D, Eigen::Vector2d(0.0, -2.0)).has_value());
  // Below the peak there are two preimages; the one inside the fold is returned.
  const auto x = Undistort(D, Eigen::Vector2d(0.5, 0.0));
  ASSERT_TRUE(x.has_value());
  EXPECT_LT(x->norm(), 0.861);
  EXPECT_NEAR(Distort(D, *x).x(), 0.5, 1e-12);
  // The strong lens: distorted radius 1.0 lies beyond the peak (~0.95).
  EXPECT_FALSE(Undistort(StrongD(), Eigen::Vector2d(0.8, 0.6)).has_value());
}

TEST(Distortion, NonFiniteInputReturnsNullopt) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(Undistort(KittiD(), Eigen::Vector2d(nan, 0)).has_value());
  EXPECT_FALSE(Undistort(KittiD(), Eigen::Vector2d(0, inf)).has_value());
  RadTanDistortion bad = KittiD();
  bad.k2 = nan;
  EXPECT_FALSE(Undistort(bad, Eigen::Vector2d(0.1, 0.1)).has_value());
  PinholeIntrinsics badK = KittiK();
  badK.fx = 0;
  EXPECT_FALSE(UndistortPixel(badK, KittiD(), Eigen::Vector2d(10, 10)).has_value());
  EXPECT_FALSE(DistortPixel(KittiK(), KittiD(), Eigen::Vector2d(nan, 1)).has_value());
}

TEST(Distortion, SegmentEndpoints) {
  const PinholeIntrinsics K = KittiK();
  const RadTanDistortion D = KittiD();
  const Eigen::Vector2d s(100, 50), e(1300, 480);
  const auto seg = UndistortSegment(K, D, *DistortPixel(K, D, s), *DistortPixel(K, D, e));
  ASSERT_TRUE(seg.has_value());
  EXPECT_LT((seg->first - s).norm(), 1e-8);
  EXPECT_LT((seg->second - e).norm(), 1e-8);
  EXPECT_FALSE(UndistortSegment(K, D, s, Eigen::Vector2d(std::nan(""), 0)).has_value());
}

}  // namespace
}  // namespace plucker
