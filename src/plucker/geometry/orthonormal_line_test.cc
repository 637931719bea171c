#include "plucker/geometry/orthonormal_line.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>

#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace {

using verify::Rng;

Line6d Unit(const Line6d& L) { return L / L.norm(); }

// U orthonormal with det +1, u1 . u2 = 0, W unit.
void ExpectWellFormed(const OrthonormalLine& o) {
  EXPECT_NEAR(o.U.norm(), 1.0, 1e-12);
  const Eigen::Matrix3d U = o.U.toRotationMatrix();
  EXPECT_LT((U.transpose() * U - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(U.determinant(), 1.0, 1e-12);
  EXPECT_NEAR(o.W.norm(), 1.0, 1e-12);
}

TEST(OrthonormalLine, RoundTripRandomLinesAnyScale) {
  Rng rng(1);
  for (int i = 0; i < 500; ++i) {
    const Line6d L =
        verify::Uniform(rng, 0.01, 100.0) *
        LineFromPoints<double>(verify::RandomVector(rng, 10), verify::RandomVector(rng, 10));
    const auto o = OrthonormalFromPlucker(L);
    ASSERT_TRUE(o);
    ExpectWellFormed(*o);
    EXPECT_GE(o->W(0), 0.0);
    EXPECT_GT(o->W(1), 0.0);
    // Positive scale: (w1 u1, w2 u2) = L / |L| exactly (the sign is kept).
    EXPECT_LT((PluckerFromOrthonormal(*o) - Unit(L)).norm(), 1e-12);
    // Through the stored parameters too.
    double p[6];
    o->ToParameters(p);
    EXPECT_LT((PluckerFromOrthonormal<double>(p) - Unit(L)).norm(), 1e-12);
    // Distance of the line from the origin = w1 / w2.
    EXPECT_NEAR(o->W(0) / o->W(1), (*NormalizeLineDirection(L)).head<3>().norm(), 1e-9);
  }
}

TEST(OrthonormalLine, NegativeScaleIsTheSameLine) {
  const Line6d L = LineFromPoints<double>(Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(-2, 0, 1));
  const Line6d back = PluckerFromOrthonormal(*OrthonormalFromPlucker(-3.0 * L));
  EXPECT_LT((back + Unit(L)).norm(), 1e-12);
}

TEST(OrthonormalLine, LinesThroughTheOriginAreDeterministic) {
  Rng rng(2);
  for (int i = 0; i < 100; ++i) {
    Eigen::Vector3d d = verify::RandomUnitVector(rng);
    if (i < 3) d = Eigen::Vector3d::Unit(i);  // along each axis, incl. z
    Line6d L;
    L << 0, 0, 0, 2.5 * d;
    const auto o = OrthonormalFromPlucker(L);
    ASSERT_TRUE(o);
    ExpectWellFormed(*o);
    EXPECT_EQ(o->W(0), 0.0);
    EXPECT_EQ(o->W(1), 1.0);
    EXPECT_LT((PluckerFromOrthonormal(*o) - Unit(L)).norm(), 1e-12);
    const auto o2 = OrthonormalFromPlucker(L);
    EXPECT_EQ(o->U.coeffs(), o2->U.coeffs());  // deterministic
  }
}

// Reproduces the gimbal-lock case of the notes: n = (0,0,1), d = (1,0,0) puts u1 on world z,
// where ZYX Euler angles lose a degree of freedom and a conversion returns another line. Here the
// round trip is exact and the tangent still spans 4 independent directions.
TEST(OrthonormalLine, FirstAxisAlongWorldZ) {
  const Line6d L = (Line6d() << 0, 0, 1, 1, 0, 0).finished();
  const auto o = OrthonormalFromPlucker(L);
  ASSERT_TRUE(o);
  ExpectWellFormed(*o);
  EXPECT_LT((o->U.toRotationMatrix().col(0) - Eigen::Vector3d::UnitZ()).norm(), 1e-15);
  EXPECT_LT((PluckerFromOrthonormal(*o) - Unit(L)).norm(), 1e-15);
  Eigen::Matrix<double, 6, 4> J;
  PluckerFromOrthonormal(*o, &J);
  Eigen::JacobiSVD<Eigen::Matrix<double, 6, 4>> svd(J);
  EXPECT_GT(svd.singularValues()(3), 0.5);  // rank 4: no lost degree of freedom
  // Small steps along each tangent direction give distinct lines, and Minus recovers them.
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector4d delta = 1e-3 * Eigen::Vector4d::Unit(k);
    const OrthonormalLine moved = o->Plus(delta);
    EXPECT_GT((PluckerFromOrthonormal(moved) - PluckerFromOrthonormal(*o)).norm(), 4e-4);
    EXPECT_LT((moved.Minus(*o) - delta).norm(), 1e-15);
  }
}

// The 6x4 Jacobian against central differences, and the short published version with the sign of
// the w2 u3 entry flipped: the check must tell them apart.
TEST(OrthonormalLine, JacobianMatchesDifferencesAndRejectsFlippedSign) {
  Rng rng(3);
  for (int i = 0; i < 50; ++i) {
    OrthonormalLine o;
    o.U = verify::RandomRotation(rng);
    const double phi = verify::Uniform(rng, 0.1, 1.4);
    o.W = Eigen::Vector2d(std::cos(phi), std::sin(phi));
    Eigen::Matrix<double, 6, 4> J;
    PluckerFromOrthonormal(o, &J);
    Eigen::Matrix<double, 6, 4> numeric;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector4d h = 1e-6 * Eigen::Vector4d::Unit(k);
      numeric.col(k) =
          (PluckerFromOrthonormal(o.Plus(h)) - PluckerFromOrthonormal(o.Plus(-h))) / 2e-6;
    }
    EXPECT_LT((J - numeric).norm(), 1e-8);
    Eigen::Matrix<double, 6, 4> flipped = J;
    flipped.block<3, 1>(3, 0) = -flipped.block<3, 1>(3, 0);  // -w2 u3
    EXPECT_GT((flipped - numeric).norm(), 0.1);
  }
}

TEST(OrthonormalLine, PlusMinusAreInverse) {
  Rng rng(4);
  for (int i = 0; i < 200; ++i) {
    OrthonormalLine x;
    x.U = i == 0 ? verify::RotationNearPi(rng, 0.0) : verify::RandomRotation(rng);
    const double phi = verify::Uniform(rng, -M_PI, M_PI);
    x.W = Eigen::Vector2d(std::cos(phi), std::sin(phi));
    Eigen::Vector4d delta;
    delta << verify::RandomUnitVector(rng) * verify::Uniform(rng, 0.0, 3.0),
        verify::Uniform(rng, -3.0, 3.0);
    EXPECT_LT((x.Plus(delta).Minus(x) - delta).norm(), 1e-12);
    OrthonormalLine y;
    y.U = verify::RandomRotation(rng);
    y.W = Eigen::Vector2d(verify::Uniform(rng, -1, 1), verify::Uniform(rng, -1, 1)).normalized();
    const OrthonormalLine back = x.Plus(y.Minus(x));
    EXPECT_LT((back.U.coeffs() - y.U.coeffs()).norm(), 1e-12);
    EXPECT_LT((back.W - y.W).norm(), 1e-12);
  }
}

TEST(OrthonormalLine, ParametersNormalisedOnRead) {
  const double p[6] = {0.2, -0.4, 0.1, 0.9, 3.0, 4.0};
  const OrthonormalLine o = OrthonormalLine::FromParameters(p);
  ExpectWellFormed(o);
  EXPECT_NEAR(o.W(0), 0.6, 1e-15);
  double scaled[6];
  for (int i = 0; i < 6; ++i) scaled[i] = p[i] * (i < 4 ? 2.0 : 0.5);
  EXPECT_LT((PluckerFromOrthonormal<double>(scaled) - PluckerFromOrthonormal(o)).norm(), 1e-15);
}

TEST(OrthonormalLine, RejectsDegenerateInput) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(OrthonormalFromPlucker(Line6d::Zero()));
  EXPECT_FALSE(OrthonormalFromPlucker((Line6d() << 1, 0, 0, 0, 0, 0).finished()));
  EXPECT_FALSE(OrthonormalFromPlucker((Line6d() << nan, 0, 0, 0, 1, 0).finished()));
  EXPECT_FALSE(OrthonormalFromPlucker(
      (Line6d() << 0, 0, 0, std::numeric_limits<double>::infinity(), 0, 0).finished()));
  // A gross constraint violation (n . d != 0) is refused, rounding-size ones are projected away.
  EXPECT_FALSE(OrthonormalFromPlucker((Line6d() << 1, 1, 0, 1, 0, 0).finished()));
  const auto o = OrthonormalFromPlucker((Line6d() << 1e-12, 1, 0, 1, 0, 0).finished());
  ASSERT_TRUE(o);
  ExpectWellFormed(*o);
  EXPECT_LT((PluckerFromOrthonormal(*o) - Unit((Line6d() << 0, 1, 0, 1, 0, 0).finished())).norm(),
            1e-11);
}

}  // namespace
}  // namespace plucker
