#include "plucker/factors/pose_manifold.h"

#include <ceres/manifold_test_utils.h>
#include <gtest/gtest.h>

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

TEST(PoseManifold, RejectsNonFiniteInput) {
  PoseManifold manifold;
  double x[7] = {0, 0, 0, 1, 0, 0, std::nan("")};
  double delta[6] = {0, 0, 0, 0, 0, 0};
  double out[7];
  double jac[42];
  EXPECT_FALSE(manifold.Plus(x, delta, out));
  EXPECT_FALSE(manifold.PlusJacobian(x, jac));
}

}  // namespace
}  // namespace plucker
