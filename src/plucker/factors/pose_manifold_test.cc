#include "plucker/factors/pose_manifold.h"

#include <ceres/manifold_test_utils.h>
#include <gtest/gtest.h>

#include "plucker/factors/pose_block.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace {

TEST(PoseManifold, InvariantsHoldOnRandomAndHardPoints) {
  PoseManifold manifold;
  verify::Rng rng(11);
  for (int i = 0; i < 200; ++i) {
    SE3d x = verify::RandomPose(rng);
    if (i == 0) x = SE3d();
    if (i == 1) x = SE3d(verify::RotationNearPi(rng, 0.0), Eigen::Vector3d(1, 2, 3));
    double xp[7];
    x.ToParameters(xp);
    Vector6d delta;
    delta << verify::RandomUnitVector(rng) * verify::Uniform(rng, 0, 1.0),
        verify::RandomVector(rng);
    if (i == 2) delta.setZero();
    SE3d y = verify::RandomPose(rng);
    double yp[7];
    y.ToParameters(yp);
    // y must be within the region where Minus inverts Plus (rotation distance < pi).
    using namespace ceres;  // the macro names ceres' helpers unqualified
    const Vector xv = Eigen::Map<const Vector>(xp, 7), yv = Eigen::Map<const Vector>(yp, 7);
    const Vector dv = delta;
    EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(manifold, xv, dv, yv, 1e-9);
  }
}

// Ceres' invariants on the 2-dimensional sub-manifold: y is a point of it (Plus of x), as
// Minus(y, x) inverts Plus only there; Plus keeps the position, and yaw is no tangent direction.
TEST(RollPitchPoseManifold, InvariantsHoldAndPositionAndYawStay) {
  RollPitchPoseManifold manifold;
  verify::Rng rng(12);
  int checked = 0;
  for (int i = 0; i < 200; ++i) {
    SE3d x = verify::RandomPose(rng);
    if (i == 0) x = SE3d();
    if (i == 1) x = SE3d(verify::RotationNearPi(rng, 0.0), Eigen::Vector3d(1, 2, 3));
    double xp[7], yp[7];
    x.ToParameters(xp);
    Eigen::Vector2d delta = verify::RandomVector(rng).head<2>(), to_y = delta.reverse() * 0.5;
    if (i == 2) delta.setZero();
    ASSERT_TRUE(manifold.Plus(xp, to_y.data(), yp));
    using namespace ceres;  // the macro names ceres' helpers unqualified
    const Vector xv = Eigen::Map<const Vector>(xp, 7), yv = Eigen::Map<const Vector>(yp, 7);
    const Vector dv = delta;
    EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(manifold, xv, dv, yv, 1e-9);
    // Plus keeps the position; a change of yaw alone (a world z rotation) is no tangent
    // direction: Minus sees none of it.
    EXPECT_LT((SE3d::FromParameters(yp).translation() - x.translation()).norm(), 1e-12);
    const SE3d yawed(
        Eigen::Quaterniond(Eigen::AngleAxisd(1e-4, Eigen::Vector3d::UnitZ())) * x.rotation(),
        x.translation());
    double zp[7], z_minus_x[2];
    yawed.ToParameters(zp);
    ASSERT_TRUE(manifold.Minus(zp, xp, z_minus_x));
    EXPECT_LT(Eigen::Map<Eigen::Vector2d>(z_minus_x).norm(), 1e-12);
    ++checked;
  }
  EXPECT_EQ(checked, 200);
}

TEST(PoseManifold, RejectsNonFiniteInput) {
  PoseManifold manifold;
  double x[7] = {0, 0, 0, 1, 0, 0, std::nan("")};
  double delta[6] = {0, 0, 0, 0, 0, 0};
  double out[7];
  double jac[42];
  EXPECT_FALSE(manifold.Plus(x, delta, out));
  EXPECT_FALSE(manifold.PlusJacobian(x, jac));
}

// The one tangent-to-ambient conversion of the analytic factors, against its definition.
TEST(PoseBlock, WriteAmbientIsTangentTimesMinusJacobian) {
  PoseManifold manifold;
  verify::Rng rng(12);
  for (int i = 0; i < 100; ++i) {
    double x[7];
    verify::RandomPose(rng).ToParameters(x);
    for (int k = 0; k < 4; ++k) x[k] *= verify::Uniform(rng, 0.5, 2.0);  // not normalised
    Eigen::Quaterniond q;
    Eigen::Vector3d t;
    ASSERT_TRUE(pose_block::Read(x, &q, nullptr, &t));
    const Eigen::Matrix<double, 3, 6> J_tangent = Eigen::Matrix<double, 3, 6>::Random();
    Eigen::Matrix<double, 6, 7, Eigen::RowMajor> M;
    ASSERT_TRUE(manifold.MinusJacobian(x, M.data()));
    Eigen::Matrix<double, 3, 7, Eigen::RowMajor> J;
    pose_block::WriteAmbient<3>(J_tangent.leftCols<3>(), J_tangent.rightCols<3>(), q, J.data());
    EXPECT_LT((J - J_tangent * M).norm(), 1e-14 * (1.0 + J.norm()));
  }
}

TEST(PoseBlock, ReadRefusesNonFiniteZeroAndOverflowingQuaternions) {
  Eigen::Quaterniond q;
  Eigen::Vector3d t;
  for (const double qx : {std::nan(""), 0.0, 1e200}) {
    const double x[7] = {qx, 0, 0, qx == 0.0 ? 0.0 : 1e200, 1, 2, 3};
    EXPECT_FALSE(pose_block::Read(x, &q, nullptr, &t)) << qx;
  }
}

}  // namespace
}  // namespace plucker
