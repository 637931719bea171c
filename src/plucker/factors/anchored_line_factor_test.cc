#include "plucker/factors/anchored_line_factor.h"

#include <ceres/problem.h>
#include <ceres/solver.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "plucker/factors/line_manifold.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/geometry/line_projection.h"
#include "plucker/geometry/orthonormal_line.h"
#include "plucker/verify/checks.h"
#include "plucker/verify/jacobian_check.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace {

const PinholeIntrinsics kK{400.0, 400.0, 319.5, 239.5};

// Projects the segment p1_w-p2_w into a camera (noise-free endpoints).
void ProjectSegment(const SE3d& T_w_c, const Eigen::Vector3d& p1_w, const Eigen::Vector3d& p2_w,
                    Eigen::Vector2d* s, Eigen::Vector2d* e) {
  const SE3d T_c_w = T_w_c.Inverse();
  const Eigen::Vector3d a = T_c_w * p1_w, b = T_c_w * p2_w;
  *s = Eigen::Vector2d(kK.fx * a.x() / a.z() + kK.cx, kK.fy * a.y() / a.z() + kK.cy);
  *e = Eigen::Vector2d(kK.fx * b.x() / b.z() + kK.cx, kK.fy * b.y() / b.z() + kK.cy);
}

// The registered checks factor.line.Anchored.tangent, factor.line.AnchoredVI.tangent and
// factor.line.AnchoredVI.time_offset (factors/time_offset_factor.h)
// (verify/line_factor_checks.cc: a camera 1 km from the origin, rotations near pi, random
// extrinsics), against autodiff and Ridders differences; the guarded sample is refused by both.
TEST(AnchoredLineFactor, JacobianChecksPass) {
  verify::JacobianCheckOptions options;
  options.samples = 1000;
  options.seed = 11;
  const verify::JacobianCheckRun run =
      verify::RunJacobianChecks(verify::FactorJacobianChecks(), "factor.line.Anchored", 4, options);
  EXPECT_TRUE(run.ok()) << run.error;
  for (const verify::JacobianCheckStats& s : run.stats) {
    EXPECT_EQ(s.skipped, 1) << s.name;
    RecordProperty(s.name, s.WorstErrors());
  }
}

// The link T_w_c = T_w_b T_b_c: its tangent Jacobians against central differences through
// SE3::Plus / Minus (the PoseManifold's).
TEST(CameraFromBody, TangentJacobiansMatchCentralDifferences) {
  verify::Rng rng(7);
  int checked = 0;
  for (int i = 0; i < 100; ++i) {
    const SE3d T_w_b = verify::RandomPose(rng), T_b_c = verify::RandomPose(rng);
    Matrix6d J_wb, J_bc;
    const SE3d T_w_c = CameraFromBody(T_w_b, T_b_c, &J_wb, &J_bc);
    ASSERT_LT((T_w_c.Matrix() - (T_w_b * T_b_c).Matrix()).norm(), 1e-12);
    Matrix6d N_wb, N_bc;
    const double h = 1e-6;
    for (int k = 0; k < 6; ++k) {
      const Vector6d d = Vector6d::Unit(k) * h;
      N_wb.col(k) =
          ((T_w_b.Plus(d) * T_b_c).Minus(T_w_c) - (T_w_b.Plus(-d) * T_b_c).Minus(T_w_c)) / (2 * h);
      N_bc.col(k) =
          ((T_w_b * T_b_c.Plus(d)).Minus(T_w_c) - (T_w_b * T_b_c.Plus(-d)).Minus(T_w_c)) / (2 * h);
    }
    EXPECT_LT((J_wb - N_wb).norm(), 1e-6 * (1.0 + J_wb.norm())) << "sample " << i;
    EXPECT_LT((J_bc - N_bc).norm(), 1e-6 * (1.0 + J_bc.norm())) << "sample " << i;
    ++checked;
  }
  EXPECT_EQ(checked, 100);
}

TEST(AnchoredLineFactorVI, EqualsTheCameraFactorOnTheComposedPoseAndHonoursAHeldExtrinsic) {
  verify::Rng rng(3);
  const SE3d T_w_c = verify::RandomPose(rng), T_b_c = verify::RandomPose(rng);
  const Eigen::Vector3d p1 = T_w_c * Eigen::Vector3d(-1, 0.5, 4),
                        p2 = T_w_c * Eigen::Vector3d(1, -0.2, 6);
  const Line6d L_w = LineFromPoints<double>(p1, p2);
  const LineAnchor anchor = MakeLineAnchor(L_w, T_w_c.translation());
  Eigen::Vector2d s, e;
  ProjectSegment(T_w_c, p1, p2, &s, &e);
  s += Eigen::Vector2d(3.0, -4.0);
  const std::unique_ptr<ceres::CostFunction> vi(
      AnchoredLineFactorVI::Create(kK, s, e, Eigen::Matrix2d::Identity(), anchor));
  const std::unique_ptr<ceres::CostFunction> mono(
      AnchoredLineFactor::Create(kK, s, e, Eigen::Matrix2d::Identity(), anchor));
  double pose_b[7], pose_bc[7], pose_c[7], line[6];
  (T_w_c * T_b_c.Inverse()).ToParameters(pose_b);
  T_b_c.ToParameters(pose_bc);
  T_w_c.ToParameters(pose_c);
  OrthonormalFromPlucker(AnchoredFromWorld(L_w, anchor))->ToParameters(line);
  const double* pv[3] = {pose_b, pose_bc, line};
  const double* pm[2] = {pose_c, line};
  double rv[2], rm[2], J0[14], J2[12];
  double* jv[3] = {J0, nullptr, J2};
  ASSERT_TRUE(vi->Evaluate(pv, rv, jv));
  ASSERT_TRUE(mono->Evaluate(pm, rm, nullptr));
  EXPECT_NEAR(rv[0], rm[0], 1e-9);
  EXPECT_NEAR(rv[1], rm[1], 1e-9);
  EXPECT_GT(std::hypot(rv[0], rv[1]), 0.01);  // a residual that checks something
  // The held extrinsic (null jacobians[1]) leaves the other Jacobians as they are.
  double F0[14], F1[14], F2[12], rf[2];
  double* jf[3] = {F0, F1, F2};
  ASSERT_TRUE(vi->Evaluate(pv, rf, jf));
  for (int k = 0; k < 14; ++k) EXPECT_EQ(J0[k], F0[k]);
  for (int k = 0; k < 12; ++k) EXPECT_EQ(J2[k], F2[k]);
}

TEST(AnchoredLineFactor, AnchoringRoundTripsAndKeepsTheResidual) {
  const Line6d L_w =
      LineFromPoints<double>(Eigen::Vector3d(1000, 2, 5), Eigen::Vector3d(1003, 1, 6));
  const LineAnchor anchor = MakeLineAnchor(L_w, Eigen::Vector3d(998, 0, 0));
  const Line6d L_a = AnchoredFromWorld(L_w, anchor);
  // The anchored line is at distance 1 from the anchor origin.
  EXPECT_NEAR(L_a.head<3>().norm() / L_a.tail<3>().norm(), 1.0, 1e-9);
  const Line6d back = WorldFromAnchored(L_a, anchor);
  EXPECT_LT((back - L_w).norm(), 1e-9 * L_w.norm());
}

// Refines one line with every camera fixed from a perturbed start; the Ceres iterations.
int RefineLineIterations(const Eigen::Vector3d& offset, bool anchored, double* final_error) {
  // Five cameras 0.5 m apart looking along +z at a segment 6 m ahead; everything moved by offset.
  std::vector<SE3d> cams;
  for (int i = 0; i < 5; ++i)
    cams.emplace_back(Eigen::Quaterniond::Identity(),
                      offset + Eigen::Vector3d(0.5 * i, 0.1 * i, 0));
  const Eigen::Vector3d p1 = offset + Eigen::Vector3d(-1.0, -0.5, 6.0);
  const Eigen::Vector3d p2 = offset + Eigen::Vector3d(2.0, 0.7, 7.0);
  const Line6d L_true = LineFromPoints<double>(p1, p2);
  // The same physical perturbation in both cases: endpoints moved by ~20 cm.
  const Line6d L_start = LineFromPoints<double>(p1 + Eigen::Vector3d(0.15, -0.1, 0.2),
                                                p2 + Eigen::Vector3d(-0.1, 0.2, -0.25));
  const LineAnchor anchor =
      anchored ? MakeLineAnchor(L_start, cams[0].translation()) : LineAnchor{};
  double block[6];
  OrthonormalFromPlucker(AnchoredFromWorld(L_start, anchor))->ToParameters(block);
  std::vector<std::array<double, 7>> poses(cams.size());
  LineManifold line_manifold;
  ceres::Problem::Options po;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  for (std::size_t i = 0; i < cams.size(); ++i) {
    cams[i].ToParameters(poses[i].data());
    Eigen::Vector2d s, e;
    ProjectSegment(cams[i], p1, p2, &s, &e);
    problem.AddResidualBlock(
        AnchoredLineFactor::Create(kK, s, e, Eigen::Matrix2d::Identity(), anchor), nullptr,
        poses[i].data(), block);
    problem.SetParameterBlockConstant(poses[i].data());
  }
  problem.SetManifold(block, &line_manifold);
  ceres::Solver::Options so;
  so.max_num_iterations = 500;
  so.function_tolerance = 1e-14;
  so.gradient_tolerance = 1e-16;
  so.parameter_tolerance = 1e-14;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  const Line6d L_a = PluckerFromOrthonormal(OrthonormalLine::FromParameters(block));
  const Line6d L_est = WorldFromAnchored(L_a, anchor);
  // Distance of the true endpoints from the estimated line.
  *final_error = std::max(*PointLineDistance(L_est, p1), *PointLineDistance(L_est, p2));
  (void)L_true;
  return static_cast<int>(summary.iterations.size()) - 1;
}

TEST(AnchoredLineFactor, FarLinesConvergeAsFastAsNearOnes) {
  const Eigen::Vector3d near = Eigen::Vector3d::Zero();
  const Eigen::Vector3d far(800.0, -600.0, 50.0);  // 1 km from the world origin
  double e[4];
  const int near_world = RefineLineIterations(near, false, &e[0]);
  const int far_world = RefineLineIterations(far, false, &e[1]);
  const int near_anchored = RefineLineIterations(near, true, &e[2]);
  const int far_anchored = RefineLineIterations(far, true, &e[3]);
  std::printf(
      "line refinement iterations: near %d / far %d in the world frame, near %d / far %d "
      "anchored (final endpoint errors %.1e %.1e %.1e %.1e m)\n",
      near_world, far_world, near_anchored, far_anchored, e[0], e[1], e[2], e[3]);
  for (double x : e) EXPECT_LT(x, 1e-6);
  EXPECT_LE(far_anchored, near_anchored + 1);
  EXPECT_LT(far_anchored, far_world);
}

}  // namespace
}  // namespace plucker
