#include "plucker/geometry/se3.h"

#include <gtest/gtest.h>

#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace {

TEST(SO3, ExpLogRoundTripIncludingNearZeroAndNearPi) {
  verify::Rng rng(7);
  for (int i = 0; i < 1000; ++i) {
    const double angle = i == 0   ? 0.0
                         : i == 1 ? 1e-12
                         : i == 2 ? M_PI
                                  : verify::Uniform(rng, 0, M_PI);
    const Eigen::Vector3d w = verify::RandomUnitVector(rng) * angle;
    const Eigen::Vector3d w2 = LogSO3<double>(ExpSO3<double>(w));
    if (angle > M_PI - 1e-9) {
      // At pi, w and -w are the same rotation.
      EXPECT_LT(std::min((w2 - w).norm(), (w2 + w).norm()), 1e-9);
    } else {
      EXPECT_LT((w2 - w).norm(), 1e-12 + 1e-12 * angle) << w.transpose();
    }
  }
}

TEST(SO3, LogOfNegatedQuaternionIsTheSameRotation) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()));
  Eigen::Quaterniond qn(q);
  qn.coeffs() = -qn.coeffs();
  EXPECT_LT((LogSO3<double>(q) - LogSO3<double>(qn)).norm(), 1e-15);
}

TEST(SE3, PlusMinusRoundTrip) {
  verify::Rng rng(8);
  for (int i = 0; i < 1000; ++i) {
    const SE3d a = verify::RandomPose(rng);
    Vector6d d;
    d << verify::RandomUnitVector(rng) * verify::Uniform(rng, 0, M_PI - 1e-3),
        verify::RandomVector(rng);
    EXPECT_LT((a.Plus(d).Minus(a) - d).norm(), 1e-9);
  }
}

TEST(SE3, CompositionAndInverse) {
  verify::Rng rng(9);
  for (int i = 0; i < 1000; ++i) {
    const SE3d a = verify::RandomPose(rng), b = verify::RandomPose(rng);
    const Eigen::Vector3d p = verify::RandomVector(rng, 3);
    EXPECT_LT(((a * b) * p - a * (b * p)).norm(), 1e-12);
    EXPECT_LT((a.Inverse() * (a * p) - p).norm(), 1e-12);
    EXPECT_LT(((a * b).Matrix() - a.Matrix() * b.Matrix()).norm(), 1e-12);
  }
}

TEST(SE3, ParameterBlockLayoutIsQuaternionXYZWThenTranslation) {
  const SE3d a(Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ())),
               Eigen::Vector3d(1, 2, 3));
  double p[7];
  a.ToParameters(p);
  EXPECT_DOUBLE_EQ(p[3], std::cos(0.25));
  EXPECT_DOUBLE_EQ(p[2], std::sin(0.25));
  EXPECT_DOUBLE_EQ(p[4], 1.0);
  EXPECT_DOUBLE_EQ(p[6], 3.0);
  EXPECT_LT((SE3d::FromParameters(p).Matrix() - a.Matrix()).norm(), 1e-15);
}

}  // namespace
}  // namespace plucker
