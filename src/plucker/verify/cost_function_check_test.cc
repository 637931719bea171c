// The shared factor-check loop catches planted mistakes of the math reference ("known mistakes"):
// the wrong sign of the line Jacobian's translation block, tangent Jacobians written where the
// ambient ones belong, and refusals the two versions disagree on.
#include "plucker/verify/cost_function_check.h"

#include <gtest/gtest.h>

#include "plucker/factors/line_manifold.h"
#include "plucker/factors/line_reprojection_factor.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/geometry/orthonormal_line.h"

namespace plucker {
namespace verify {
namespace {

using Edit = std::function<bool(double const* const*, double**)>;  // false: refuse

// The analytic line factor with its Jacobians edited after Evaluate.
class Planted final : public ceres::CostFunction {
 public:
  Planted(ceres::CostFunction* f, Edit edit) : f_(f), edit_(std::move(edit)) {
    *mutable_parameter_block_sizes() = f->parameter_block_sizes();
    set_num_residuals(f->num_residuals());
  }
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    return f_->Evaluate(p, r, J) && (!J || edit_(p, J));
  }

 private:
  std::unique_ptr<ceres::CostFunction> f_;
  Edit edit_;
};

// 100 samples of the line factor with the analytic Jacobians edited.
JacobianCheckStats RunPlanted(Edit edit, bool expect_refusal = false) {
  const PoseManifold pose;
  const LineManifold line;
  JacobianCheckOptions o;
  o.samples = 100;
  return RunCostFunctionCheck("planted", 7, o, [&](Rng& rng, int) {
    const PinholeIntrinsics K{500.0, 500.0, 320.0, 240.0};
    const SE3d T_w_c = RandomPose(rng);
    const Eigen::Vector3d p1 = RandomVector(rng) + Eigen::Vector3d(0, 0, 5),
                          p2 = RandomVector(rng) + Eigen::Vector3d(0, 0, 5);
    const Eigen::Vector2d s = K.ToPixel<double>(p1.head<2>() / p1.z());
    const Eigen::Vector2d e = K.ToPixel<double>(p2.head<2>() / p2.z()) + Eigen::Vector2d(1, -2);
    CostFunctionSample c;
    c.analytic.reset(
        new Planted(LineReprojectionFactor::Create(K, s, e, Eigen::Matrix2d::Identity()), edit));
    c.autodiff.reset(LineReprojectionFactor::CreateAutoDiff(K, s, e, Eigen::Matrix2d::Identity()));
    c.x = {Eigen::VectorXd(7), Eigen::VectorXd(6)};
    T_w_c.ToParameters(c.x[0].data());
    OrthonormalFromPlucker(LineFromPoints<double>(T_w_c * p1, T_w_c * p2))
        ->ToParameters(c.x[1].data());
    c.manifolds = {&pose, &line};
    c.expect_refusal = expect_refusal;
    return c;
  });
}

TEST(CostFunctionCheck, PassesTheRightFactorAndCatchesPlantedMistakes) {
  const JacobianCheckStats ok = RunPlanted([](auto, auto) { return true; });
  EXPECT_TRUE(ok.passed()) << ok.first_failure;
  EXPECT_EQ(ok.samples, 100);

  // -R^T [d_w]x instead of R^T [d_w]x: the translation columns negated.
  const JacobianCheckStats sign = RunPlanted([](auto, double** J) {
    for (int r = 0; r < 2; ++r)
      for (int c = 4; c < 7; ++c) J[0][7 * r + c] = -J[0][7 * r + c];
    return true;
  });
  EXPECT_EQ(sign.failures, 100);
  EXPECT_GT(sign.worst_autodiff, 1e-3);
  EXPECT_GT(sign.worst_numeric, 1e-3);

  // The tangent line Jacobian (2 x 4) written into the ambient block (2 x 6), zero-padded.
  const JacobianCheckStats tangent = RunPlanted([](double const* const* p, double** J) {
    Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> J_line(J[1]);
    const Eigen::Matrix<double, 2, 4> J_tan = J_line * LinePlusJacobian(p[1]);
    J_line << J_tan, Eigen::Matrix2d::Zero();
    return true;
  });
  EXPECT_EQ(tangent.failures, 100);
  EXPECT_GT(tangent.worst_autodiff, 1e-3);
  EXPECT_GT(tangent.worst_numeric, 1e-3);
}

TEST(CostFunctionCheck, RefusalsMustAgreeWithTheTwinAndTheExpectation) {
  const JacobianCheckStats one_refuses = RunPlanted([](auto, auto) { return false; });
  EXPECT_EQ(one_refuses.failures, 100);
  EXPECT_EQ(one_refuses.skipped, 0);
  const JacobianCheckStats unexpected = RunPlanted([](auto, auto) { return true; }, true);
  EXPECT_EQ(unexpected.failures, 100);
  EXPECT_NE(unexpected.first_failure.find("refusal mismatch"), std::string::npos);
}

}  // namespace
}  // namespace verify
}  // namespace plucker
