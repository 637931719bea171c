#include "plucker/factors/line_reprojection_factor.h"

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "plucker/factors/line_manifold.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/verify/jacobian_check.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace {

using verify::Rng;
const double kNaN = std::numeric_limits<double>::quiet_NaN();

PinholeIntrinsics TestIntrinsics() { return {500.0, 505.0, 320.0, 240.0}; }

// A camera at `centre` looking at the origin (z forward, y roughly down).
SE3d LookAtOrigin(const Eigen::Vector3d& centre) {
  const Eigen::Vector3d z = (-centre).normalized();
  Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
  if (x.norm() < 1e-6) x = z.cross(Eigen::Vector3d::UnitX());
  x.normalize();
  Eigen::Matrix3d R;
  R << x, z.cross(x), z;
  return SE3d(R, centre);
}

// Synthetic world segments inside a 4 m cube at the origin (built here, not from the sim module).
struct Segment {
  Eigen::Vector3d a, b;
  Line6d L() const { return LineFromPoints(a, b); }
};
std::vector<Segment> RandomSegments(Rng& rng, int count) {
  std::vector<Segment> segments;
  for (int i = 0; i < count; ++i) {
    Segment s{verify::RandomVector(rng, 2.0), verify::RandomVector(rng, 2.0)};
    if ((s.a - s.b).norm() < 0.5) {
      --i;
      continue;
    }
    segments.push_back(s);
  }
  return segments;
}

Eigen::Vector2d Project(const PinholeIntrinsics& K, const SE3d& T_w_c, const Eigen::Vector3d& p_w) {
  const Eigen::Vector3d p_c = T_w_c.Inverse() * p_w;
  return K.ToPixel<double>(p_c.head<2>() / p_c.z());
}

std::vector<double> PoseBlock(const SE3d& T) {
  std::vector<double> p(7);
  T.ToParameters(p.data());
  return p;
}
std::vector<double> LineBlock(const Line6d& L) {
  std::vector<double> p(6);
  OrthonormalFromPlucker(L)->ToParameters(p.data());
  return p;
}

double RotationError(const SE3d& a, const SE3d& b) {
  return LogSO3<double>(a.rotation().conjugate() * b.rotation()).norm();
}

// Same line up to scale and sign.
double LineError(const Line6d& a, const Line6d& b) {
  const Line6d an = a / a.norm(), bn = b / b.norm();
  return std::min((an - bn).norm(), (an + bn).norm());
}

// ---------------------------------------------------------------------------------------------

TEST(LineReprojectionFactor, ResidualIsSignedPixelDistanceAndMatchesTwin) {
  const PinholeIntrinsics K = TestIntrinsics();
  const SE3d T_w_c = LookAtOrigin(Eigen::Vector3d(1, -2, -7));
  const Segment seg{Eigen::Vector3d(-1, 0.5, 0.2), Eigen::Vector3d(1.2, -0.3, 0.4)};
  const Eigen::Vector2d s = Project(K, T_w_c, seg.a), e = Project(K, T_w_c, seg.b);
  // Move the endpoints perpendicular to the image segment by +2 px and -3 px.
  const Eigen::Vector2d dir = (e - s).normalized();
  const Eigen::Vector2d normal(-dir(1), dir(0));
  const Eigen::Matrix2d sqrt_info = 0.5 * Eigen::Matrix2d::Identity();
  std::unique_ptr<ceres::CostFunction> f(
      LineReprojectionFactor::Create(K, s + 2 * normal, e - 3 * normal, sqrt_info));
  std::unique_ptr<ceres::CostFunction> f_ad(
      LineReprojectionFactor::CreateAutoDiff(K, s + 2 * normal, e - 3 * normal, sqrt_info));
  const std::vector<double> pose = PoseBlock(T_w_c), line = LineBlock(seg.L());
  const double* params[] = {pose.data(), line.data()};
  Eigen::Vector2d r, r_ad;
  ASSERT_TRUE(f->Evaluate(params, r.data(), nullptr));
  ASSERT_TRUE(f_ad->Evaluate(params, r_ad.data(), nullptr));
  EXPECT_NEAR(std::abs(r(0)), 1.0, 1e-9);  // 0.5 * 2 px
  EXPECT_NEAR(std::abs(r(1)), 1.5, 1e-9);  // 0.5 * 3 px
  EXPECT_LT(r(0) * r(1), 0.0);             // opposite sides
  EXPECT_LT((r - r_ad).norm(), 1e-12);
}

// ceres::GradientChecker (Ridders differences in the ambient space, times PlusJacobian) with the
// manifolds. Its entry-wise relative test flags structural zeros that carry 1e-13 of rounding on
// one side (e.g. u1 parallel to z), so the tangent Jacobians are compared with the project's
// norm-wise measure (verify::JacobianError) instead of Probe's boolean.
void ExpectGradientCheckerAgrees(const ceres::CostFunction* f,
                                 const std::vector<const ceres::Manifold*>& manifolds,
                                 double const* const* params) {
  ceres::NumericDiffOptions options;
  options.ridders_relative_initial_step_size = 1e-4;
  ceres::GradientChecker checker(f, &manifolds, options);
  ceres::GradientChecker::ProbeResults results;
  checker.Probe(params, 1e-6, &results);
  ASSERT_EQ(results.local_jacobians.size(), manifolds.size()) << results.error_log;
  ASSERT_EQ(results.local_numeric_jacobians.size(), manifolds.size()) << results.error_log;
  for (size_t k = 0; k < manifolds.size(); ++k) {
    EXPECT_LT(verify::JacobianError(results.local_jacobians[k], results.local_numeric_jacobians[k]),
              1e-6)
        << "block " << k << "\n"
        << results.error_log;
  }
}

// ceres' own gradient checker with the two manifolds, on random and hard configurations.
TEST(LineReprojectionFactor, GradientCheckerWithManifolds) {
  const PinholeIntrinsics K = TestIntrinsics();
  PoseManifold pose_manifold;
  LineManifold line_manifold;
  const std::vector<const ceres::Manifold*> manifolds = {&pose_manifold, &line_manifold};
  Rng rng(5);
  for (int i = 0; i < 30; ++i) {
    SE3d T_w_c = LookAtOrigin(verify::RandomUnitVector(rng) * verify::Uniform(rng, 5, 10));
    if (i == 0) T_w_c = SE3d(verify::RotationNearPi(rng, 0.0), Eigen::Vector3d::Zero());
    Segment seg = RandomSegments(rng, 1)[0];
    if (i == 0) seg = {T_w_c * Eigen::Vector3d(-1, 0.2, 4), T_w_c * Eigen::Vector3d(1, -0.3, 6)};
    if (i == 1) {  // n = (0,0,1), d = (1,0,0): u1 along world z
      T_w_c = SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.3, -1.2, -5));
      seg = {Eigen::Vector3d(-1, -1, 0), Eigen::Vector3d(1, -1, 0)};
    }
    const Eigen::Vector2d s = Project(K, T_w_c, seg.a) + Eigen::Vector2d(1.5, -2.0);
    const Eigen::Vector2d e = Project(K, T_w_c, seg.b) + Eigen::Vector2d(-0.5, 1.0);
    std::unique_ptr<ceres::CostFunction> f(
        LineReprojectionFactor::Create(K, s, e, Eigen::Matrix2d::Identity()));
    const std::vector<double> pose = PoseBlock(T_w_c), line = LineBlock(seg.L());
    const double* params[] = {pose.data(), line.data()};
    ExpectGradientCheckerAgrees(f.get(), manifolds, params);
  }
}

TEST(LineReprojectionFactorVI, GradientCheckerWithManifolds) {
  const PinholeIntrinsics K = TestIntrinsics();
  PoseManifold pose_manifold;
  LineManifold line_manifold;
  const std::vector<const ceres::Manifold*> manifolds = {&pose_manifold, &pose_manifold,
                                                         &line_manifold};
  Rng rng(6);
  for (int i = 0; i < 30; ++i) {
    const SE3d T_w_c = LookAtOrigin(verify::RandomUnitVector(rng) * verify::Uniform(rng, 5, 10));
    const SE3d T_b_c = i == 0 ? SE3d(verify::RotationNearPi(rng, 0.0), Eigen::Vector3d(0.1, 0, 0))
                              : SE3d(verify::RandomRotation(rng), verify::RandomVector(rng, 0.3));
    const SE3d T_w_b = T_w_c * T_b_c.Inverse();
    const Segment seg = RandomSegments(rng, 1)[0];
    const Eigen::Vector2d s = Project(K, T_w_c, seg.a) + Eigen::Vector2d(1.5, -2.0);
    const Eigen::Vector2d e = Project(K, T_w_c, seg.b) + Eigen::Vector2d(-0.5, 1.0);
    std::unique_ptr<ceres::CostFunction> f(
        LineReprojectionFactorVI::Create(K, s, e, Eigen::Matrix2d::Identity()));
    const std::vector<double> body = PoseBlock(T_w_b), ext = PoseBlock(T_b_c),
                              line = LineBlock(seg.L());
    const double* params[] = {body.data(), ext.data(), line.data()};
    ExpectGradientCheckerAgrees(f.get(), manifolds, params);
  }
}

// With T_b_c = identity the VI factor is the monocular factor; jacobians[1] == nullptr is honoured.
TEST(LineReprojectionFactorVI, MatchesMonocularAndSkipsNullJacobians) {
  const PinholeIntrinsics K = TestIntrinsics();
  Rng rng(7);
  const SE3d T_w_c = LookAtOrigin(Eigen::Vector3d(2, 6, -3));
  const Segment seg = RandomSegments(rng, 1)[0];
  const Eigen::Vector2d s = Project(K, T_w_c, seg.a) + Eigen::Vector2d(1, 2);
  const Eigen::Vector2d e = Project(K, T_w_c, seg.b) + Eigen::Vector2d(-3, 1);
  std::unique_ptr<ceres::CostFunction> mono(
      LineReprojectionFactor::Create(K, s, e, Eigen::Matrix2d::Identity()));
  std::unique_ptr<ceres::CostFunction> vi(
      LineReprojectionFactorVI::Create(K, s, e, Eigen::Matrix2d::Identity()));
  const std::vector<double> pose = PoseBlock(T_w_c), ident = PoseBlock(SE3d()),
                            line = LineBlock(seg.L());
  const double* p_mono[] = {pose.data(), line.data()};
  const double* p_vi[] = {pose.data(), ident.data(), line.data()};
  Eigen::Vector2d r_mono, r_vi;
  Eigen::Matrix<double, 2, 7, Eigen::RowMajor> J_pose_mono, J_pose_vi;
  Eigen::Matrix<double, 2, 6, Eigen::RowMajor> J_line_mono, J_line_vi;
  double* j_mono[] = {J_pose_mono.data(), J_line_mono.data()};
  double* j_vi[] = {J_pose_vi.data(), nullptr, J_line_vi.data()};
  ASSERT_TRUE(mono->Evaluate(p_mono, r_mono.data(), j_mono));
  ASSERT_TRUE(vi->Evaluate(p_vi, r_vi.data(), j_vi));
  EXPECT_LT((r_mono - r_vi).norm(), 1e-9);
  EXPECT_LT((J_pose_mono - J_pose_vi).norm(), 1e-9 * J_pose_mono.norm());
  EXPECT_LT((J_line_mono - J_line_vi).norm(), 1e-9 * J_line_mono.norm());
}

// ---------------------------------------------------------------------------------------------
// Bad input.

TEST(LineReprojectionFactor, CreateRejectsBadMeasurements) {
  const PinholeIntrinsics K = TestIntrinsics();
  const Eigen::Vector2d s(100, 100), e(300, 200);
  const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
  PinholeIntrinsics bad_K = K;
  bad_K.fx = 0.0;
  Eigen::Matrix2d nan_info = I;
  nan_info(0, 1) = kNaN;
  using Fn = ceres::CostFunction* (*)(const PinholeIntrinsics&, const Eigen::Vector2d&,
                                      const Eigen::Vector2d&, const Eigen::Matrix2d&);
  for (Fn create : {static_cast<Fn>(&LineReprojectionFactor::Create),
                    static_cast<Fn>(&LineReprojectionFactor::CreateAutoDiff),
                    static_cast<Fn>(&LineReprojectionFactorVI::Create),
                    static_cast<Fn>(&LineReprojectionFactorVI::CreateAutoDiff)}) {
    EXPECT_THROW(create(K, s, s, I), std::invalid_argument);  // zero-length segment
    EXPECT_THROW(create(K, Eigen::Vector2d(kNaN, 1), e, I), std::invalid_argument);
    EXPECT_THROW(create(K, s, Eigen::Vector2d(1, std::numeric_limits<double>::infinity()), I),
                 std::invalid_argument);
    EXPECT_THROW(create(bad_K, s, e, I), std::invalid_argument);
    EXPECT_THROW(create(K, s, e, nan_info), std::invalid_argument);
    std::unique_ptr<ceres::CostFunction> ok(create(K, s, e, I));
    EXPECT_NE(ok, nullptr);
  }
}

TEST(LineReprojectionFactor, EvaluateRefusesBadParametersAndDegenerateLines) {
  const PinholeIntrinsics K = TestIntrinsics();
  const SE3d T_w_c = LookAtOrigin(Eigen::Vector3d(0, 0, -6));
  const Eigen::Vector2d s(100, 100), e(300, 200);
  std::unique_ptr<ceres::CostFunction> fs[] = {
      std::unique_ptr<ceres::CostFunction>(
          LineReprojectionFactor::Create(K, s, e, Eigen::Matrix2d::Identity())),
      std::unique_ptr<ceres::CostFunction>(
          LineReprojectionFactor::CreateAutoDiff(K, s, e, Eigen::Matrix2d::Identity()))};
  const std::vector<double> pose = PoseBlock(T_w_c);
  const Segment seg{Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d(1, 0.5, 0)};
  const std::vector<double> line = LineBlock(seg.L());
  // Along the optical axis through the camera centre: projects to a point.
  const std::vector<double> axis_line = LineBlock(
      LineFromPoints<double>(T_w_c * Eigen::Vector3d(0, 0, 1), T_w_c * Eigen::Vector3d(0, 0, 2)));
  // In the camera's principal plane: projects to the line at infinity.
  const std::vector<double> plane_line = LineBlock(
      LineFromPoints<double>(T_w_c * Eigen::Vector3d(1, 0, 0), T_w_c * Eigen::Vector3d(0, 1, 0)));
  std::vector<double> nan_pose = pose, zero_q = pose, nan_line = line, zero_w = line;
  nan_pose[5] = kNaN;
  zero_q[0] = zero_q[1] = zero_q[2] = zero_q[3] = 0.0;
  nan_line[4] = kNaN;
  zero_w[4] = zero_w[5] = 0.0;
  for (auto& f : fs) {
    Eigen::Vector2d r;
    Eigen::Matrix<double, 2, 7, Eigen::RowMajor> J0;
    Eigen::Matrix<double, 2, 6, Eigen::RowMajor> J1;
    double* jac[] = {J0.data(), J1.data()};
    auto eval = [&](const std::vector<double>& p, const std::vector<double>& l) {
      const double* params[] = {p.data(), l.data()};
      const bool ok = f->Evaluate(params, r.data(), jac);
      if (ok) {
        EXPECT_TRUE(r.allFinite() && J0.allFinite() && J1.allFinite());
      }
      return ok;
    };
    EXPECT_TRUE(eval(pose, line));
    EXPECT_FALSE(eval(pose, axis_line));
    EXPECT_FALSE(eval(pose, plane_line));
    EXPECT_FALSE(eval(nan_pose, line));
    EXPECT_FALSE(eval(pose, nan_line));
    EXPECT_FALSE(eval(zero_q, line));
    EXPECT_FALSE(eval(pose, zero_w));
  }
}

// ---------------------------------------------------------------------------------------------
// Convergence with noise-free synthetic data.

ceres::Solver::Options TightOptions() {
  ceres::Solver::Options options;
  options.max_num_iterations = 100;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  options.num_threads = 1;
  return options;
}

TEST(LineReprojectionFactor, RecoversCameraPoseFromLinesOnly) {
  const PinholeIntrinsics K = TestIntrinsics();
  Rng rng(8);
  const SE3d T_w_c_gt = LookAtOrigin(Eigen::Vector3d(2, -3, -7));
  const std::vector<Segment> segments = RandomSegments(rng, 24);
  Eigen::Matrix<double, 6, 1> perturbation;
  perturbation << 0.05, -0.04, 0.03, 0.3, -0.2, 0.25;
  std::vector<double> pose = PoseBlock(T_w_c_gt.Plus(perturbation));
  std::vector<std::vector<double>> lines;
  for (const Segment& seg : segments) lines.push_back(LineBlock(seg.L()));

  ceres::Problem problem;
  problem.AddParameterBlock(pose.data(), 7, new PoseManifold);
  for (size_t i = 0; i < segments.size(); ++i) {
    problem.AddResidualBlock(LineReprojectionFactor::Create(K, Project(K, T_w_c_gt, segments[i].a),
                                                            Project(K, T_w_c_gt, segments[i].b),
                                                            Eigen::Matrix2d::Identity()),
                             nullptr, pose.data(), lines[i].data());
    problem.SetManifold(lines[i].data(), new LineManifold);
    problem.SetParameterBlockConstant(lines[i].data());
  }
  ceres::Solver::Summary summary;
  ceres::Solve(TightOptions(), &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
  const SE3d T_est = SE3d::FromParameters(pose.data());
  EXPECT_LT(RotationError(T_est, T_w_c_gt), 1e-6) << summary.BriefReport();
  EXPECT_LT((T_est.translation() - T_w_c_gt.translation()).norm(), 1e-6);
}

TEST(LineReprojectionFactor, RefinesLinesWithKnownPoses) {
  const PinholeIntrinsics K = TestIntrinsics();
  Rng rng(9);
  std::vector<SE3d> cameras;
  for (int i = 0; i < 5; ++i) {
    cameras.push_back(LookAtOrigin(
        Eigen::Vector3d(8 * std::cos(0.3 * i), 1.0 - 0.5 * i, -8 * std::sin(0.3 * i + 0.8))));
  }
  const std::vector<Segment> segments = RandomSegments(rng, 20);
  std::vector<std::vector<double>> poses, lines;
  for (const SE3d& T : cameras) poses.push_back(PoseBlock(T));
  LineManifold manifold;
  for (const Segment& seg : segments) {
    std::vector<double> block_gt = LineBlock(seg.L()), start(6);
    Eigen::Vector4d delta;
    delta << verify::RandomVector(rng, 0.03), verify::Uniform(rng, -0.03, 0.03);
    manifold.Plus(block_gt.data(), delta.data(), start.data());
    lines.push_back(start);
  }
  ceres::Problem problem;
  for (auto& p : poses) {
    problem.AddParameterBlock(p.data(), 7, new PoseManifold);
    problem.SetParameterBlockConstant(p.data());
  }
  for (size_t j = 0; j < segments.size(); ++j) {
    problem.AddParameterBlock(lines[j].data(), 6, new LineManifold);
    for (size_t i = 0; i < cameras.size(); ++i) {
      problem.AddResidualBlock(
          LineReprojectionFactor::Create(K, Project(K, cameras[i], segments[j].a),
                                         Project(K, cameras[i], segments[j].b),
                                         Eigen::Matrix2d::Identity()),
          nullptr, poses[i].data(), lines[j].data());
    }
  }
  ceres::Solver::Summary summary;
  ceres::Solve(TightOptions(), &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
  for (size_t j = 0; j < segments.size(); ++j) {
    EXPECT_LT(LineError(PluckerFromOrthonormal<double>(lines[j].data()), segments[j].L()), 1e-8)
        << "line " << j;
  }
}

// The extrinsic held constant: ceres passes jacobians[1] == nullptr to the VI factor.
TEST(LineReprojectionFactorVI, RecoversBodyPoseWithConstantExtrinsic) {
  const PinholeIntrinsics K = TestIntrinsics();
  Rng rng(10);
  const SE3d T_b_c(ExpSO3<double>(Eigen::Vector3d(-1.2, 0.1, 0.3)),
                   Eigen::Vector3d(0.1, -0.05, 0.2));
  const SE3d T_w_c = LookAtOrigin(Eigen::Vector3d(-3, 2, -7));
  const SE3d T_w_b_gt = T_w_c * T_b_c.Inverse();
  const std::vector<Segment> segments = RandomSegments(rng, 22);
  Eigen::Matrix<double, 6, 1> perturbation;
  perturbation << -0.04, 0.05, 0.02, -0.2, 0.3, 0.1;
  std::vector<double> body = PoseBlock(T_w_b_gt.Plus(perturbation)), ext = PoseBlock(T_b_c);
  std::vector<std::vector<double>> lines;
  for (const Segment& seg : segments) lines.push_back(LineBlock(seg.L()));
  ceres::Problem problem;
  problem.AddParameterBlock(body.data(), 7, new PoseManifold);
  problem.AddParameterBlock(ext.data(), 7, new PoseManifold);
  problem.SetParameterBlockConstant(ext.data());
  for (size_t i = 0; i < segments.size(); ++i) {
    problem.AddParameterBlock(lines[i].data(), 6, new LineManifold);
    problem.SetParameterBlockConstant(lines[i].data());
    problem.AddResidualBlock(LineReprojectionFactorVI::Create(K, Project(K, T_w_c, segments[i].a),
                                                              Project(K, T_w_c, segments[i].b),
                                                              Eigen::Matrix2d::Identity()),
                             nullptr, body.data(), ext.data(), lines[i].data());
  }
  ceres::Solver::Summary summary;
  ceres::Solve(TightOptions(), &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
  const SE3d T_est = SE3d::FromParameters(body.data());
  EXPECT_LT(RotationError(T_est, T_w_b_gt), 1e-6) << summary.BriefReport();
  EXPECT_LT((T_est.translation() - T_w_b_gt.translation()).norm(), 1e-6);
  EXPECT_EQ(ext, PoseBlock(T_b_c));  // untouched
}

// The registered checks of both factors (verify/line_factor_checks.cc); the curated guard sample
// (a line along the optical axis through the camera centre) is refused by both versions and
// counted as skipped.
TEST(LineReprojectionFactor, JacobianChecksPass) {
  verify::JacobianCheckOptions options;
  options.samples = 1000;
  options.seed = 7;
  const verify::JacobianCheckRun run = verify::RunJacobianChecks(
      verify::FactorJacobianChecks(), "factor.line.Reprojection", 4, options);
  EXPECT_TRUE(run.ok()) << run.error;
  for (const verify::JacobianCheckStats& s : run.stats) {
    EXPECT_EQ(s.skipped, 1) << s.name;
    RecordProperty(s.name, s.WorstErrors());
  }
}

}  // namespace
}  // namespace plucker
