#include "plucker/factors/line_manifold.h"

#include <ceres/manifold_test_utils.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "plucker/geometry/orthonormal_line.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace {

using verify::Rng;

// Random points plus the hard ones: u1 parallel to world z, phi = 0 and near 0 (far lines),
// phi = pi/2 and near it (lines through / near the origin), U at and near a rotation by pi.
OrthonormalLine SamplePoint(Rng& rng, int i) {
  OrthonormalLine x;
  x.U = verify::RandomRotation(rng);
  const double phi = verify::Uniform(rng, -M_PI, M_PI);
  x.W = Eigen::Vector2d(std::cos(phi), std::sin(phi));
  switch (i) {
    case 0:
      x = *OrthonormalFromPlucker((Line6d() << 0, 0, 1, 1, 0, 0).finished());
      break;
    case 1:
      x.W = Eigen::Vector2d(1, 0);
      break;
    case 2:
      x.W = Eigen::Vector2d(std::cos(1e-8), std::sin(1e-8));
      break;
    case 3:
      x.W = Eigen::Vector2d(0, 1);
      break;
    case 4:
      x.W = Eigen::Vector2d(std::cos(M_PI / 2 - 1e-8), std::sin(M_PI / 2 - 1e-8));
      break;
    case 5:
      x.U = verify::RotationNearPi(rng, 0.0);
      break;
    case 6:
      x.U = verify::RotationNearPi(rng, 1e-7);
      break;
    case 7:
      x.U = Eigen::Quaterniond(0, 0, 0, 1);
      break;  // w = 0 exactly
    default:
      break;
  }
  return x;
}

TEST(LineManifold, InvariantsHoldOnRandomAndHardPoints) {
  LineManifold manifold;
  Rng rng(21);
  for (int i = 0; i < 300; ++i) {
    const OrthonormalLine x = SamplePoint(rng, i % 10 == 9 ? 100 : i);
    const OrthonormalLine y = SamplePoint(rng, (i + 3) % 12);
    double xp[6], yp[6];
    x.ToParameters(xp);
    y.ToParameters(yp);
    Eigen::Vector4d delta;
    delta << verify::RandomUnitVector(rng) * verify::Uniform(rng, 0, 1.0),
        verify::Uniform(rng, -1, 1);
    if (i == 1) delta.setZero();
    using namespace ceres;  // the macro names ceres' helpers unqualified
    const Vector xv = Eigen::Map<const Vector>(xp, 6), yv = Eigen::Map<const Vector>(yp, 6);
    const Vector dv = delta;
    EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(manifold, xv, dv, yv, 1e-9);
  }
}

TEST(LineManifold, PlusJacobianIsTheTrueDerivative) {
  // Not a fake [I; 0]: compare with central differences of Plus in storage coordinates.
  LineManifold manifold;
  Rng rng(22);
  for (int i = 0; i < 20; ++i) {
    double x[6];
    SamplePoint(rng, i).ToParameters(x);
    Eigen::Matrix<double, 6, 4, Eigen::RowMajor> J;
    ASSERT_TRUE(manifold.PlusJacobian(x, J.data()));
    Eigen::Matrix<double, 6, 4> numeric;
    for (int k = 0; k < 4; ++k) {
      double dp[4] = {0, 0, 0, 0}, dm[4] = {0, 0, 0, 0};
      dp[k] = 1e-6;
      dm[k] = -1e-6;
      Eigen::Matrix<double, 6, 1> xp, xm;
      ASSERT_TRUE(manifold.Plus(x, dp, xp.data()));
      ASSERT_TRUE(manifold.Plus(x, dm, xm.data()));
      numeric.col(k) = (xp - xm) / 2e-6;
    }
    EXPECT_LT((Eigen::Matrix<double, 6, 4>(J) - numeric).norm(), 1e-8);
    Eigen::Matrix<double, 4, 6, Eigen::RowMajor> M;
    ASSERT_TRUE(manifold.MinusJacobian(x, M.data()));
    EXPECT_LT((M * J - Eigen::Matrix4d::Identity()).norm(), 1e-12);
  }
}

TEST(LineManifold, RejectsNonFiniteAndZeroInput) {
  LineManifold manifold;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double good[6] = {0, 0, 0, 1, 0.6, 0.8};
  const double bad_nan[6] = {0, 0, 0, 1, nan, 0.8};
  const double bad_q[6] = {0, 0, 0, 0, 0.6, 0.8};
  const double bad_w[6] = {0, 0, 0, 1, 0, 0};
  const double delta[4] = {0, 0, 0, 0};
  const double bad_delta[4] = {0, std::numeric_limits<double>::infinity(), 0, 0};
  double out[6], jac[24], minus[4];
  for (const double* x : {bad_nan, bad_q, bad_w}) {
    EXPECT_FALSE(manifold.Plus(x, delta, out));
    EXPECT_FALSE(manifold.PlusJacobian(x, jac));
    EXPECT_FALSE(manifold.MinusJacobian(x, jac));
    EXPECT_FALSE(manifold.Minus(x, good, minus));
    EXPECT_FALSE(manifold.Minus(good, x, minus));
  }
  EXPECT_FALSE(manifold.Plus(good, bad_delta, out));
  EXPECT_TRUE(manifold.Plus(good, delta, out));
}

}  // namespace
}  // namespace plucker
