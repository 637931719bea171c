#include "plucker/factors/point_reprojection_factor.h"

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

#include "plucker/factors/held_extrinsic_factor.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/verify/checks.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace {

using CostPtr = std::unique_ptr<ceres::CostFunction>;
using Eigen::Vector2d;
using Eigen::Vector3d;
using RowMajor23 = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;
using RowMajor27 = Eigen::Matrix<double, 2, 7, Eigen::RowMajor>;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

PinholeIntrinsics TestCamera() { return {500, 510, 320, 240}; }

TEST(PointReprojectionFactor, CreateRejectsBadInput) {
  const PinholeIntrinsics K = TestCamera();
  const Vector2d uv(100, 200);
  const Eigen::Matrix2d S = Eigen::Matrix2d::Identity();
  PinholeIntrinsics bad = K;
  bad.fx = 0;
  PinholeIntrinsics nan_k = K;
  nan_k.cy = kNaN;
  Eigen::Matrix2d bad_S = S;
  bad_S(0, 1) = kNaN;
  for (auto create :
       {PointReprojectionFactor::Create, PointReprojectionFactor::CreateAutoDiff,
        PointReprojectionFactorVI::Create, PointReprojectionFactorVI::CreateAutoDiff}) {
    EXPECT_THROW(CostPtr(create(bad, uv, S)), std::invalid_argument);
    EXPECT_THROW(CostPtr(create(nan_k, uv, S)), std::invalid_argument);
    EXPECT_THROW(CostPtr(create(K, Vector2d(kNaN, 1), S)), std::invalid_argument);
    EXPECT_THROW(CostPtr(create(K, uv, bad_S)), std::invalid_argument);
    EXPECT_NO_THROW(CostPtr(create(K, uv, S)));
  }
}

TEST(PointReprojectionFactor, ResidualMatchesProjection) {
  verify::Rng rng(1);
  const PinholeIntrinsics K = TestCamera();
  for (int i = 0; i < 50; ++i) {
    const SE3d T_w_c = verify::RandomPose(rng);
    const Vector3d p_c(verify::Uniform(rng, -2, 2), verify::Uniform(rng, -2, 2),
                       verify::Uniform(rng, 1, 10));
    const Vector3d p_w = T_w_c * p_c;
    const Vector2d uv(verify::Uniform(rng, 0, 640), verify::Uniform(rng, 0, 480));
    const Eigen::Matrix2d S = Eigen::Vector2d(0.5, 2.0).asDiagonal();
    const CostPtr f(PointReprojectionFactor::Create(K, uv, S));
    double x[7];
    T_w_c.ToParameters(x);
    const double* params[] = {x, p_w.data()};
    Vector2d r;
    ASSERT_TRUE(f->Evaluate(params, r.data(), nullptr));
    const Vector2d expected = S * (*ProjectPoint(K, T_w_c, p_w) - uv);
    EXPECT_LT((r - expected).norm(), 1e-9);
  }
}

TEST(PointReprojectionFactor, EvaluateRejectsBadParameters) {
  const PinholeIntrinsics K = TestCamera();
  const CostPtr f(
      PointReprojectionFactor::Create(K, Vector2d(320, 240), Eigen::Matrix2d::Identity()));
  const CostPtr f_vi(
      PointReprojectionFactorVI::Create(K, Vector2d(320, 240), Eigen::Matrix2d::Identity()));
  double pose[7] = {0, 0, 0, 1, 0, 0, 0};
  double ext[7] = {0, 0, 0, 1, 0, 0, 0};
  double point[3] = {0.1, 0.2, 5.0};
  Vector2d r;
  RowMajor27 J0, J1;
  RowMajor23 J2;
  double* jac[] = {J0.data(), J2.data()};
  double* jac_vi[] = {J0.data(), J1.data(), J2.data()};
  const double* params[] = {pose, point};
  const double* params_vi[] = {pose, ext, point};
  ASSERT_TRUE(f->Evaluate(params, r.data(), jac));
  ASSERT_TRUE(f_vi->Evaluate(params_vi, r.data(), jac_vi));
  // Behind the camera and exactly in the camera's principal plane.
  for (double z : {-5.0, 0.0}) {
    point[2] = z;
    EXPECT_FALSE(f->Evaluate(params, r.data(), jac));
    EXPECT_FALSE(f_vi->Evaluate(params_vi, r.data(), jac_vi));
  }
  point[2] = 5.0;
  for (double* block : {pose, ext, point}) {
    const int n = block == point ? 3 : 7;
    for (int i = 0; i < n; ++i) {
      const double saved = block[i];
      block[i] = kNaN;
      if (block != ext) {
        EXPECT_FALSE(f->Evaluate(params, r.data(), jac));
      }
      EXPECT_FALSE(f_vi->Evaluate(params_vi, r.data(), jac_vi));
      block[i] = saved;
    }
  }
  double zero_q[7] = {0, 0, 0, 0, 0, 0, 0};
  const double* params_zero[] = {zero_q, point};
  EXPECT_FALSE(f->Evaluate(params_zero, r.data(), jac));
}

TEST(PointReprojectionFactor, JacobianChecksPass) {
  verify::JacobianCheckOptions options;
  options.samples = 1000;
  const verify::JacobianCheckRun run =
      verify::RunJacobianChecks(verify::PointFactorJacobianChecks(), "factor.point.", 4, options);
  EXPECT_TRUE(run.ok()) << run.error;
}

TEST(PointReprojectionFactor, GradientCheckerWithPoseManifold) {
  verify::Rng rng(7);
  const PinholeIntrinsics K = TestCamera();
  PoseManifold pose_manifold;
  const std::vector<const ceres::Manifold*> mono = {&pose_manifold, nullptr};
  const std::vector<const ceres::Manifold*> vi = {&pose_manifold, &pose_manifold, nullptr};
  ceres::NumericDiffOptions options;
  options.ridders_relative_initial_step_size = 1e-4;  // see lidar_factors_test.cc
  for (int i = 0; i < 20; ++i) {
    const SE3d T_w_b = verify::RandomPose(rng), T_b_c = verify::RandomPose(rng, 0.2);
    const Vector3d p_c(verify::Uniform(rng, -2, 2), verify::Uniform(rng, -2, 2),
                       verify::Uniform(rng, 1, 10));
    const Vector3d p_w = T_w_b * (T_b_c * p_c);
    const Vector2d uv(verify::Uniform(rng, 0, 640), verify::Uniform(rng, 0, 480));
    const Eigen::Matrix2d S = Eigen::Matrix2d::Identity() * 0.7;
    double x_wc[7], x_wb[7], x_bc[7];
    (T_w_b * T_b_c).ToParameters(x_wc);
    T_w_b.ToParameters(x_wb);
    T_b_c.ToParameters(x_bc);
    const double* params[] = {x_wc, p_w.data()};
    const double* params_vi[] = {x_wb, x_bc, p_w.data()};
    const CostPtr f(PointReprojectionFactor::Create(K, uv, S));
    const CostPtr f_vi(PointReprojectionFactorVI::Create(K, uv, S));
    ceres::GradientChecker::ProbeResults results;
    ceres::GradientChecker checker(f.get(), &mono, options);
    EXPECT_TRUE(checker.Probe(params, 1e-7, &results)) << results.error_log;
    ceres::GradientChecker checker_vi(f_vi.get(), &vi, options);
    EXPECT_TRUE(checker_vi.Probe(params_vi, 1e-7, &results)) << results.error_log;
  }
}

TEST(PointReprojectionFactorVI, ConstantExtrinsicJacobianMayBeOmitted) {
  verify::Rng rng(8);
  const PinholeIntrinsics K = TestCamera();
  const SE3d T_w_b = verify::RandomPose(rng), T_b_c = verify::RandomPose(rng, 0.2);
  const Vector3d p_w = T_w_b * (T_b_c * Vector3d(0.3, -0.2, 4.0));
  const CostPtr f(
      PointReprojectionFactorVI::Create(K, Vector2d(300, 250), Eigen::Matrix2d::Identity()));
  double x_wb[7], x_bc[7];
  T_w_b.ToParameters(x_wb);
  T_b_c.ToParameters(x_bc);
  const double* params[] = {x_wb, x_bc, p_w.data()};
  RowMajor27 J0, J1, J0b;
  RowMajor23 J2, J2b;
  Vector2d r, rb;
  double* all[] = {J0.data(), J1.data(), J2.data()};
  double* without_extrinsic[] = {J0b.data(), nullptr, J2b.data()};
  ASSERT_TRUE(f->Evaluate(params, r.data(), all));
  ASSERT_TRUE(f->Evaluate(params, rb.data(), without_extrinsic));
  EXPECT_EQ(r, rb);
  EXPECT_EQ(J0, J0b);
  EXPECT_EQ(J2, J2b);
}

// Recover a body pose from known points with the VI factor and a constant extrinsic.
TEST(PointReprojectionFactorVI, RecoversBodyPoseWithConstantExtrinsic) {
  verify::Rng rng(9);
  const PinholeIntrinsics K = TestCamera();
  const SE3d T_w_b_gt = verify::RandomPose(rng, 3.0);
  const SE3d T_b_c(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5), Vector3d(0.1, 0.02, -0.05));
  std::vector<Vector3d> points;
  std::vector<Vector2d> pixels;
  for (int i = 0; i < 60; ++i) {
    const Vector3d p_c(verify::Uniform(rng, -3, 3), verify::Uniform(rng, -2, 2),
                       verify::Uniform(rng, 3, 15));
    points.push_back(T_w_b_gt * (T_b_c * p_c));
    pixels.push_back(*ProjectCameraPoint(K, p_c));
  }
  Vector6d delta;
  delta << verify::RandomUnitVector(rng) * 0.05, verify::RandomUnitVector(rng) * 0.2;
  double x_wb[7], x_bc[7];
  T_w_b_gt.Plus(delta).ToParameters(x_wb);
  T_b_c.ToParameters(x_bc);
  ceres::Problem problem;
  for (size_t i = 0; i < points.size(); ++i) {
    problem.AddResidualBlock(
        PointReprojectionFactorVI::Create(K, pixels[i], Eigen::Matrix2d::Identity()), nullptr, x_wb,
        x_bc, points[i].data());
    problem.SetParameterBlockConstant(points[i].data());
  }
  problem.SetManifold(x_wb, new PoseManifold);
  problem.SetManifold(x_bc, new PoseManifold);
  problem.SetParameterBlockConstant(x_bc);
  ceres::Solver::Options options;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
  const Vector6d err = SE3d::FromParameters(x_wb).Minus(T_w_b_gt);
  EXPECT_LT(err.norm(), 1e-8) << summary.BriefReport();
  EXPECT_EQ(SE3d::FromParameters(x_bc).Minus(T_b_c).norm(), 0.0);
}

// The window's adaptor with the extrinsic held: the VI factor's residual and its T_w_b and point
// Jacobians, exactly, on random configurations.
TEST(HeldExtrinsicFactor, EqualsTheVisualInertialFactorWithoutTheExtrinsicBlock) {
  verify::Rng rng(9);
  const PinholeIntrinsics K = TestCamera();
  int checked = 0;
  for (int i = 0; i < 50; ++i) {
    const SE3d T_w_b = verify::RandomPose(rng), T_b_c = verify::RandomPose(rng, 0.2);
    const Vector3d p_w =
        T_w_b * (T_b_c * Vector3d(verify::Uniform(rng, -2, 2), verify::Uniform(rng, -2, 2),
                                  verify::Uniform(rng, 1, 10)));
    const Vector2d uv(verify::Uniform(rng, 0, 640), verify::Uniform(rng, 0, 480));
    const CostPtr vi(PointReprojectionFactorVI::Create(K, uv, Eigen::Matrix2d::Identity()));
    const HeldExtrinsicFactor<3> held(
        PointReprojectionFactorVI::Create(K, uv, Eigen::Matrix2d::Identity()), T_b_c);
    double x_wb[7], x_bc[7];
    T_w_b.ToParameters(x_wb);
    T_b_c.ToParameters(x_bc);
    const double* p_vi[] = {x_wb, x_bc, p_w.data()};
    const double* p_held[] = {x_wb, p_w.data()};
    double r_vi[2], r_held[2], J_wb[14], J_bc[14], J_p[6], H_wb[14], H_p[6];
    double* j_vi[] = {J_wb, J_bc, J_p};
    double* j_held[] = {H_wb, H_p};
    ASSERT_TRUE(vi->Evaluate(p_vi, r_vi, j_vi));
    ASSERT_TRUE(held.Evaluate(p_held, r_held, j_held));
    for (int k = 0; k < 2; ++k) EXPECT_EQ(r_vi[k], r_held[k]);
    for (int k = 0; k < 14; ++k) EXPECT_EQ(J_wb[k], H_wb[k]);
    for (int k = 0; k < 6; ++k) EXPECT_EQ(J_p[k], H_p[k]);
    ASSERT_TRUE(held.Evaluate(p_held, r_held, nullptr));  // residual only
    EXPECT_EQ(r_vi[0], r_held[0]);
    ++checked;
  }
  EXPECT_EQ(checked, 50);
}

}  // namespace
}  // namespace plucker
