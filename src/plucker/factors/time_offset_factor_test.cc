#include "plucker/factors/time_offset_factor.h"

#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <stdexcept>

#include "plucker/factors/held_extrinsic_factor.h"
#include "plucker/geometry/orthonormal_line.h"
#include "plucker/verify/jacobian_check.h"

namespace plucker {
namespace {

using CostPtr = std::unique_ptr<ceres::CostFunction>;
using Eigen::Vector2d;

const PinholeIntrinsics kK{500, 510, 320, 240};

// The camera 4 m behind the world origin, a point and a line in front of it.
struct Scene {
  double T_w_b[7] = {1, 0, 0, 0, 0.1, -0.2, -4.0};
  double T_b_c[7] = {1, 0, 0, 0, 0.05, 0.0, 0.0};
  double p_w[3] = {0.3, 0.2, 1.0};
  double line[6];
  LineAnchor anchor;
  Scene() {
    const Line6d L_w =
        LineFromPoints<double>(Eigen::Vector3d(-1, 0.5, 0), Eigen::Vector3d(1, 0.7, 1));
    anchor = MakeLineAnchor(L_w, Eigen::Vector3d(0.15, -0.2, -4.0));
    OrthonormalFromPlucker(AnchoredFromWorld(L_w, anchor))->ToParameters(line);
  }
};

Vector2d Eval(const ceres::CostFunction& f, const double* const* x) {
  Vector2d r;
  EXPECT_TRUE(f.Evaluate(x, r.data(), nullptr));
  return r;
}

TEST(TimeOffsetFactor, PointMovesTheMeasurementAlongItsVelocity) {
  Scene s;
  const Vector2d uv(300, 250), v(120, -40);
  const Eigen::Matrix2d S = Eigen::Matrix2d::Identity() * 0.5;
  const CostPtr td_f(PointReprojectionFactorVITimeOffset::Create(kK, uv, v, S));
  const double td = 0.008;
  const double* x4[4] = {s.T_w_b, s.T_b_c, &td, s.p_w};
  const double* x[3] = {s.T_w_b, s.T_b_c, s.p_w};
  // The factor without time offset at the shifted measurement uv - td v.
  const CostPtr plain(PointReprojectionFactorVI::Create(kK, uv - td * v, S));
  EXPECT_LT((Eval(*td_f, x4) - Eval(*plain, x)).norm(), 1e-9);
  // With the extrinsic held, the same residual.
  HeldExtrinsicTimeOffsetFactor<3> held(PointReprojectionFactorVITimeOffset::Create(kK, uv, v, S),
                                        SE3d::FromParameters(s.T_b_c));
  const double* xh[3] = {s.T_w_b, &td, s.p_w};
  EXPECT_LT((Eval(held, xh) - Eval(*plain, x)).norm(), 1e-9);
}

TEST(TimeOffsetFactor, LineMovesTheEndpointsAlongTheirVelocities) {
  Scene s;
  const Vector2d a(200, 220), b(420, 260), va(150, 30), vb(-80, 60);
  const Eigen::Matrix2d S = Eigen::Matrix2d::Identity();
  const CostPtr td_f(AnchoredLineFactorVITimeOffset::Create(kK, a, b, va, vb, S, s.anchor));
  for (double td : {0.0, 0.008, -0.03, 0.5}) {
    const double* x4[4] = {s.T_w_b, s.T_b_c, &td, s.line};
    const double* x[3] = {s.T_w_b, s.T_b_c, s.line};
    const CostPtr plain(AnchoredLineFactorVI::Create(kK, a - td * va, b - td * vb, S, s.anchor));
    EXPECT_LT((Eval(*td_f, x4) - Eval(*plain, x)).norm(), 1e-9) << "td " << td;
  }
  // Velocities that would collapse the segment within 1 s (tau shortened): still exact.
  const CostPtr fast(AnchoredLineFactorVITimeOffset::Create(kK, a, b, b - a, a - b, S, s.anchor));
  const double td = 0.1;
  const double* x4[4] = {s.T_w_b, s.T_b_c, &td, s.line};
  const double* x[3] = {s.T_w_b, s.T_b_c, s.line};
  const CostPtr plain(
      AnchoredLineFactorVI::Create(kK, a - td * (b - a), b - td * (a - b), S, s.anchor));
  EXPECT_LT((Eval(*fast, x4) - Eval(*plain, x)).norm(), 1e-9);
}

TEST(TimeOffsetFactor, RejectsBadInput) {
  Scene s;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Eigen::Matrix2d S = Eigen::Matrix2d::Identity();
  const Vector2d a(200, 220), b(420, 260), bad(nan, 0);
  EXPECT_THROW(PointReprojectionFactorVITimeOffset::Create(kK, a, bad, S), std::invalid_argument);
  EXPECT_THROW(PointReprojectionFactorVITimeOffset::CreateAutoDiff(kK, a, bad, S),
               std::invalid_argument);
  EXPECT_THROW(AnchoredLineFactorVITimeOffset::Create(kK, a, b, bad, a, S, s.anchor),
               std::invalid_argument);
  EXPECT_THROW(AnchoredLineFactorVITimeOffset::CreateAutoDiff(kK, a, a, a, a, S, s.anchor),
               std::invalid_argument);
  const CostPtr f(PointReprojectionFactorVITimeOffset::Create(kK, a, a, S));
  const double td = nan;
  const double* x[4] = {s.T_w_b, s.T_b_c, &td, s.p_w};
  Vector2d r;
  EXPECT_FALSE(f->Evaluate(x, r.data(), nullptr));
}

// The registered checks (plucker check-jacobians) pass on their samples.
TEST(TimeOffsetFactor, JacobianChecksPass) {
  verify::JacobianCheckOptions o;
  o.samples = 200;
  const verify::JacobianCheckRun run =
      verify::RunJacobianChecks(verify::AllJacobianChecks(), ".time_offset", 2, o);
  EXPECT_TRUE(run.ok()) << run.error;
}

}  // namespace
}  // namespace plucker
