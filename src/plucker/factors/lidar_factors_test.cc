#include "plucker/factors/lidar_factors.h"

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <vector>

#include "plucker/factors/pose_manifold.h"
#include "plucker/geometry/se3.h"
#include "plucker/verify/checks.h"
#include "plucker/verify/lidar_comparison_factors.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace {

using CostPtr = std::unique_ptr<ceres::CostFunction>;
using Eigen::Vector3d;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Eval {
  bool ok = false;
  Eigen::VectorXd r;
  Eigen::Matrix<double, Eigen::Dynamic, 7, Eigen::RowMajor> J;
};

Eval Evaluate(const ceres::CostFunction& f, const double* x) {
  Eval e;
  e.r.resize(f.num_residuals());
  e.J.resize(f.num_residuals(), 7);
  double* jac[] = {e.J.data()};
  const double* params[] = {x};
  e.ok = f.Evaluate(params, e.r.data(), jac);
  return e;
}

// Distance of p from the line through a, b, computed independently of the factors.
double LineDistance(const Vector3d& p, const Vector3d& a, const Vector3d& b) {
  const Vector3d d = (b - a).normalized();
  const Vector3d v = p - a;
  return (v - v.dot(d) * d).norm();
}

TEST(LidarFactors, CreateRejectsBadInput) {
  const Vector3d p(1, 2, 3), a(0, 0, 0), b(1, 0, 0), m(0, 0, 1), q(0, 0, 1);
  const Vector3d nan(kNaN, 0, 0), inf(std::numeric_limits<double>::infinity(), 0, 0);
  using F = PointToPlaneFactor;
  EXPECT_THROW(CostPtr(F::Create(nan, m, q)), std::invalid_argument);
  EXPECT_THROW(CostPtr(F::Create(p, inf, q)), std::invalid_argument);
  EXPECT_THROW(CostPtr(F::Create(p, m, nan)), std::invalid_argument);
  EXPECT_THROW(CostPtr(F::Create(p, Vector3d::Zero(), q)), std::invalid_argument);
  EXPECT_THROW(CostPtr(F::Create(p, Vector3d(0, 0, 2), q)), std::invalid_argument);
  EXPECT_THROW(CostPtr(F::Create(p, m, q, 0.0)), std::invalid_argument);
  EXPECT_THROW(CostPtr(F::Create(p, m, q, -1.0)), std::invalid_argument);
  EXPECT_THROW(CostPtr(F::Create(p, m, q, kNaN)), std::invalid_argument);
  EXPECT_THROW(CostPtr(F::CreateAutoDiff(p, Vector3d::Zero(), q)), std::invalid_argument);
  EXPECT_NO_THROW(CostPtr(F::Create(p, Vector3d(0, 0, 1 + 1e-8), q)));

  auto edge_cases = [&](auto create) {
    EXPECT_THROW(CostPtr(create(nan, a, b, 1.0)), std::invalid_argument);
    EXPECT_THROW(CostPtr(create(p, inf, b, 1.0)), std::invalid_argument);
    EXPECT_THROW(CostPtr(create(p, a, nan, 1.0)), std::invalid_argument);
    EXPECT_THROW(CostPtr(create(p, a, a, 1.0)), std::invalid_argument);
    EXPECT_THROW(CostPtr(create(p, a, b, 0.0)), std::invalid_argument);
    EXPECT_THROW(CostPtr(create(p, a, b, -2.0)), std::invalid_argument);
    EXPECT_THROW(CostPtr(create(p, a, b, 1e-320)), std::invalid_argument);  // 1/sigma overflows
    EXPECT_THROW(CostPtr(create(p, Vector3d(-1e308, 0, 0), Vector3d(1e308, 0, 0), 1.0)),
                 std::invalid_argument);
    EXPECT_NO_THROW(CostPtr(create(p, a, Vector3d(1e-9, 0, 0), 1.0)));
  };
  edge_cases(PointToEdgeFactor::Create);
  edge_cases(PointToEdgeFactor::CreateAutoDiff);
  edge_cases(verify::PointToEdge2Factor::Create);
  edge_cases(verify::PointToEdge2Factor::CreateAutoDiff);
  edge_cases(verify::PointToEdgeScalarFactor::Create);
  edge_cases(verify::PointToEdgeScalarFactor::CreateAutoDiff);
}

// The value residuals that the LiDAR pose solver sums (PlaneResidual, EdgeResidual) are the
// factors' residuals: the same r, a tangent Jacobian that the ambient one maps back to through
// PoseManifold::PlusJacobian, and the same construction errors.
TEST(LidarFactors, ValueResidualsAreTheFactorsInTheTangent) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1, 1);
  const PoseManifold manifold;
  int compared = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const SE3d T(ExpSO3<double>(Vector3d(u(rng), u(rng), u(rng))),
                 Vector3d(5 * u(rng), 5 * u(rng), u(rng)));
    const Vector3d p(10 * u(rng), 10 * u(rng), 2 * u(rng)), q(u(rng), u(rng), u(rng));
    const Vector3d m = Vector3d(u(rng), u(rng), u(rng)).normalized();
    double x[7];
    T.ToParameters(x);
    Eigen::Matrix<double, 7, 6, Eigen::RowMajor> P;
    ASSERT_TRUE(manifold.PlusJacobian(x, P.data()));
    const Eigen::Matrix3d R = T.RotationMatrix();
    Eigen::Matrix<double, 1, 6> J_plane;
    const double r_plane =
        PlaneResidual::Create(p, m, q, 0.05).Evaluate(R, T.translation(), &J_plane);
    const Eval plane = Evaluate(*CostPtr(PointToPlaneFactor::Create(p, m, q, 0.05)), x);
    ASSERT_TRUE(plane.ok);
    EXPECT_NEAR(r_plane, plane.r(0), 1e-10 * (1 + std::abs(r_plane)));
    EXPECT_LT((J_plane - plane.J * P).norm(), 1e-10 * (1 + J_plane.norm()));
    Eigen::Matrix<double, 3, 6> J_edge;
    const Vector3d r_edge =
        EdgeResidual::CreateFromDirection(p, q, m, 0.05).Evaluate(R, T.translation(), &J_edge);
    const Eval edge = Evaluate(*CostPtr(PointToEdgeFactor::CreateFromDirection(p, q, m, 0.05)), x);
    ASSERT_TRUE(edge.ok);
    EXPECT_LT((r_edge - edge.r).norm(), 1e-10 * (1 + r_edge.norm()));
    EXPECT_LT((J_edge - edge.J * P).norm(), 1e-10 * (1 + J_edge.norm()));
    compared += 2;
  }
  EXPECT_EQ(compared, 200);
  const Vector3d p(1, 2, 3), a(0, 0, 0), m(0, 0, 1), nan(kNaN, 0, 0);
  EXPECT_THROW(PlaneResidual::Create(nan, m, a, 1.0), std::invalid_argument);
  EXPECT_THROW(PlaneResidual::Create(p, Vector3d(0, 0, 2), a, 1.0), std::invalid_argument);
  EXPECT_THROW(PlaneResidual::Create(p, m, a, 0.0), std::invalid_argument);
  EXPECT_THROW(EdgeResidual::CreateFromDirection(p, nan, m, 1.0), std::invalid_argument);
  EXPECT_THROW(EdgeResidual::CreateFromDirection(p, a, Vector3d::Zero(), 1.0),
               std::invalid_argument);
  EXPECT_THROW(EdgeResidual::CreateFromDirection(p, a, m, -1.0), std::invalid_argument);
}

TEST(LidarFactors, EvaluateRejectsNonFiniteOrZeroQuaternion) {
  const Vector3d p(1, 2, 3), a(0, 0, 0), b(1, 0, 0), m(0, 0, 1);
  std::vector<CostPtr> factors;
  factors.emplace_back(PointToPlaneFactor::Create(p, m, a));
  factors.emplace_back(PointToEdgeFactor::Create(p, a, b));
  factors.emplace_back(verify::PointToEdge2Factor::Create(p, a, b));
  factors.emplace_back(verify::PointToEdgeScalarFactor::Create(p, a, b));
  for (const auto& f : factors) {
    for (int i = 0; i < 7; ++i) {
      double x[7] = {0, 0, 0, 1, 0.1, 0.2, 0.3};
      x[i] = kNaN;
      EXPECT_FALSE(Evaluate(*f, x).ok) << "NaN at " << i;
      x[i] = std::numeric_limits<double>::infinity();
      EXPECT_FALSE(Evaluate(*f, x).ok) << "inf at " << i;
    }
    const double zero_q[7] = {0, 0, 0, 0, 1, 2, 3};
    EXPECT_FALSE(Evaluate(*f, zero_q).ok);
  }
}

TEST(LidarFactors, ResidualsAreSignedAndUnsignedDistances) {
  verify::Rng rng(3);
  for (int i = 0; i < 100; ++i) {
    const SE3d T = verify::RandomPose(rng, 3.0);
    double x[7];
    T.ToParameters(x);
    const Vector3d p_s = verify::RandomVector(rng, 5.0), a = verify::RandomVector(rng, 5.0);
    const Vector3d b = a + verify::RandomVector(rng, 2.0), m = verify::RandomUnitVector(rng);
    const double sigma = verify::Uniform(rng, 0.1, 2.0);
    const Vector3d p_w = T * p_s;
    const double distance = LineDistance(p_w, a, b);
    EXPECT_NEAR(Evaluate(*CostPtr(PointToPlaneFactor::Create(p_s, m, a, sigma)), x).r(0),
                m.dot(p_w - a) / sigma, 1e-12);
    EXPECT_NEAR(Evaluate(*CostPtr(PointToEdgeFactor::Create(p_s, a, b, sigma)), x).r.norm(),
                distance / sigma, 1e-10);
    EXPECT_NEAR(
        Evaluate(*CostPtr(verify::PointToEdge2Factor::Create(p_s, a, b, sigma)), x).r.norm(),
        distance / sigma, 1e-10);
    EXPECT_NEAR(
        Evaluate(*CostPtr(verify::PointToEdgeScalarFactor::Create(p_s, a, b, sigma)), x).r(0),
        distance / sigma, 1e-10);
  }
}

// The edge from a point and a unit direction is the two-point edge of the same line: residual
// and Jacobian agree (a second point b = a - 2.5 u gives the same u up to rounding).
TEST(LidarFactors, EdgeFromDirectionEqualsTheTwoPointForm) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int compared = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const Vector3d p_s(10 * u(rng), 10 * u(rng), 2 * u(rng)), a(u(rng), u(rng), u(rng));
    const Vector3d dir = Vector3d(u(rng), u(rng), u(rng)).normalized();
    const Eigen::Quaterniond q(ExpSO3<double>(Vector3d(u(rng), u(rng), u(rng))));
    const double x[7] = {q.x(), q.y(), q.z(), q.w(), 5 * u(rng), 5 * u(rng), u(rng)};
    const double sigma = 0.5;
    const Eval two_point =
        Evaluate(*CostPtr(PointToEdgeFactor::Create(p_s, a, a - 2.5 * dir, sigma)), x);
    const Eval from_direction =
        Evaluate(*CostPtr(PointToEdgeFactor::CreateFromDirection(p_s, a, dir, sigma)), x);
    ASSERT_TRUE(two_point.ok && from_direction.ok);
    EXPECT_LT((two_point.r - from_direction.r).norm(), 1e-12 * (1 + two_point.r.norm()));
    EXPECT_LT((two_point.J - from_direction.J).norm(), 1e-12 * (1 + two_point.J.norm()));
    ++compared;
  }
  EXPECT_EQ(compared, 50);
  const Vector3d p(1, 2, 3), a(0, 0, 0);
  EXPECT_THROW(CostPtr(PointToEdgeFactor::CreateFromDirection(p, a, Vector3d(0, 0, 2))),
               std::invalid_argument);
  EXPECT_THROW(CostPtr(PointToEdgeFactor::CreateFromDirection(p, a, Vector3d(kNaN, 0, 1))),
               std::invalid_argument);
  EXPECT_THROW(CostPtr(PointToEdgeFactor::CreateFromDirection(p, a, Vector3d::UnitZ(), 0.0)),
               std::invalid_argument);
}

TEST(LidarFactors, ScalarEdgeAtZeroDistanceReturnsZeroJacobianNotNaN) {
  // Identity pose and p_s == a: Y = u x 0 is exactly zero.
  const Vector3d a(1, 2, 3), b(2, 3, 5);
  const double x[7] = {0, 0, 0, 1, 0, 0, 0};
  for (auto create :
       {verify::PointToEdgeScalarFactor::Create, verify::PointToEdgeScalarFactor::CreateAutoDiff}) {
    const Eval e = Evaluate(*CostPtr(create(a, a, b, 0.5)), x);
    ASSERT_TRUE(e.ok);
    EXPECT_EQ(e.r(0), 0.0);
    EXPECT_TRUE(e.J.allFinite());
    EXPECT_EQ(e.J.norm(), 0.0);
  }
  // The vector form keeps a full-rank (2) Jacobian there, equal to its autodiff twin.
  const Eval an = Evaluate(*CostPtr(PointToEdgeFactor::Create(a, a, b, 0.5)), x);
  const Eval ad = Evaluate(*CostPtr(PointToEdgeFactor::CreateAutoDiff(a, a, b, 0.5)), x);
  ASSERT_TRUE(an.ok && ad.ok);
  EXPECT_EQ(an.r.norm(), 0.0);
  EXPECT_LT((an.J - ad.J).norm(), 1e-12);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(an.J.rightCols<3>());
  EXPECT_GT(svd.singularValues()(1), 1.0);
}

TEST(LidarFactors, JacobianChecksPass) {
  verify::JacobianCheckOptions options;
  options.samples = 1000;
  const verify::JacobianCheckRun run =
      verify::RunJacobianChecks(verify::LidarFactorJacobianChecks(), "factor.lidar.", 4, options);
  EXPECT_TRUE(run.ok()) << run.error;
}

TEST(LidarFactors, GradientCheckerWithPoseManifold) {
  verify::Rng rng(5);
  PoseManifold manifold;
  const std::vector<const ceres::Manifold*> manifolds = {&manifold};
  ceres::NumericDiffOptions options;
  // Ceres' checker uses Ridders' method; with its default first step (1e-2 of each value) its
  // numeric rotation columns were off by up to ~1e-3 relative on these 1-row residuals, for the
  // autodiff twins (also probed below) exactly as for the analytic factors. A smaller first step
  // makes the reference accurate.
  options.ridders_relative_initial_step_size = 1e-4;
  for (int i = 0; i < 20; ++i) {
    const SE3d T = i == 0 ? SE3d(verify::RotationNearPi(rng, 0.0), Vector3d(1, 2, 3))
                          : verify::RandomPose(rng, 3.0);
    double x[7];
    T.ToParameters(x);
    const double* params[] = {x};
    const Vector3d p_s = verify::RandomVector(rng, 10.0), a = verify::RandomVector(rng, 5.0);
    const Vector3d b = a + verify::RandomVector(rng, 2.0), m = verify::RandomUnitVector(rng);
    std::vector<CostPtr> factors;
    factors.emplace_back(PointToPlaneFactor::Create(p_s, m, a, 0.2));
    factors.emplace_back(PointToEdgeFactor::Create(p_s, a, b, 0.2));
    factors.emplace_back(verify::PointToEdge2Factor::Create(p_s, a, b, 0.2));
    factors.emplace_back(verify::PointToEdgeScalarFactor::Create(p_s, a, b, 0.2));
    factors.emplace_back(PointToPlaneFactor::CreateAutoDiff(p_s, m, a, 0.2));
    factors.emplace_back(PointToEdgeFactor::CreateAutoDiff(p_s, a, b, 0.2));
    for (const auto& f : factors) {
      ceres::GradientChecker checker(f.get(), &manifolds, options);
      ceres::GradientChecker::ProbeResults results;
      EXPECT_TRUE(checker.Probe(params, 1e-7, &results)) << "factor " << (&f - &factors[0]) << "\n"
                                                         << results.error_log;
    }
  }
}

// --- Convergence: recover a scan pose from edge and plane correspondences.

enum class EdgeForm { kVector3, kVector2 };

struct Scene {
  SE3d T_w_s_gt;
  std::vector<std::pair<Vector3d, std::pair<Vector3d, Vector3d>>> edges;   // p_s, (a_w, b_w)
  std::vector<std::pair<Vector3d, std::pair<Vector3d, Vector3d>>> planes;  // p_s, (m_w, q_w)
};

// Three walls/floor planes and four vertical/horizontal edges around the sensor; points sampled on
// them in the world, expressed in the scan frame, optionally with Gaussian noise.
Scene MakeScene(verify::Rng& rng, double noise) {
  Scene s;
  s.T_w_s_gt = SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Vector3d(0.1, 0.2, 1).normalized())),
                    Vector3d(3.0, -2.0, 1.5));
  const SE3d T_s_w = s.T_w_s_gt.Inverse();
  std::normal_distribution<double> gauss(0.0, noise > 0 ? noise : 1.0);
  auto add_noise = [&](const Vector3d& p) {
    return noise > 0 ? Vector3d(p + Vector3d(gauss(rng), gauss(rng), gauss(rng))) : p;
  };
  const std::vector<std::pair<Vector3d, double>> planes = {{Vector3d(0, 0, 1), 0.0},
                                                           {Vector3d(1, 0, 0), 12.0},
                                                           {Vector3d(0, 1, 0), -9.0},
                                                           {Vector3d(1, 1, 0).normalized(), -15.0}};
  for (const auto& [m, e] : planes) {  // m.x + e = 0
    const Vector3d origin = -e * m;
    const Vector3d t1 = m.unitOrthogonal(), t2 = m.cross(t1);
    for (int k = 0; k < 150; ++k) {
      const Vector3d p_w =
          origin + verify::Uniform(rng, -8, 8) * t1 + verify::Uniform(rng, -8, 8) * t2;
      const Vector3d q_w = origin + verify::Uniform(rng, -1, 1) * t1;
      s.planes.push_back({add_noise(T_s_w * p_w), {m, q_w}});
    }
  }
  const std::vector<std::pair<Vector3d, Vector3d>> lines = {
      {Vector3d(10, 5, 0), Vector3d(0, 0, 1)},
      {Vector3d(-6, 8, 0), Vector3d(0, 0, 1)},
      {Vector3d(0, -7, 4), Vector3d(1, 0, 0)},
      {Vector3d(7, 0, 3), Vector3d(0, 1, 0.2).normalized()}};
  for (const auto& [c, d] : lines) {
    for (int k = 0; k < 60; ++k) {
      const Vector3d p_w = c + verify::Uniform(rng, -5, 5) * d;
      const Vector3d a = c + verify::Uniform(rng, -1, 0) * d,
                     b = c + verify::Uniform(rng, 0.2, 1) * d;
      s.edges.push_back({add_noise(T_s_w * p_w), {a, b}});
    }
  }
  return s;
}

SE3d Solve(const Scene& scene, const SE3d& initial, EdgeForm form, double sigma) {
  double x[7];
  initial.ToParameters(x);
  ceres::Problem problem;
  for (const auto& [p_s, ab] : scene.edges) {
    problem.AddResidualBlock(
        form == EdgeForm::kVector3
            ? PointToEdgeFactor::Create(p_s, ab.first, ab.second, sigma)
            : verify::PointToEdge2Factor::Create(p_s, ab.first, ab.second, sigma),
        nullptr, x);
  }
  for (const auto& [p_s, mq] : scene.planes) {
    problem.AddResidualBlock(PointToPlaneFactor::Create(p_s, mq.first, mq.second, sigma), nullptr,
                             x);
  }
  problem.SetManifold(x, new PoseManifold);
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 50;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  EXPECT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
  return SE3d::FromParameters(x);
}

SE3d Perturb(const SE3d& T, verify::Rng& rng) {
  Vector6d delta;
  delta << verify::RandomUnitVector(rng) * (5.0 * M_PI / 180.0),
      verify::RandomUnitVector(rng) * 0.3;
  return T.Plus(delta);
}

TEST(LidarFactors, ConvergesToTheTruePoseNoiseFree) {
  verify::Rng rng(21);
  const Scene scene = MakeScene(rng, 0.0);
  for (EdgeForm form : {EdgeForm::kVector3, EdgeForm::kVector2}) {
    const SE3d estimate = Solve(scene, Perturb(scene.T_w_s_gt, rng), form, 0.05);
    const Vector6d err = estimate.Minus(scene.T_w_s_gt);
    EXPECT_LT(err.head<3>().norm(), 1e-6);
    EXPECT_LT(err.tail<3>().norm(), 1e-6);
  }
}

TEST(LidarFactors, ConvergesWithCentimetreNoise) {
  verify::Rng rng(22);
  const Scene scene = MakeScene(rng, 0.01);
  for (EdgeForm form : {EdgeForm::kVector3, EdgeForm::kVector2}) {
    const SE3d estimate = Solve(scene, Perturb(scene.T_w_s_gt, rng), form, 0.01);
    const Vector6d err = estimate.Minus(scene.T_w_s_gt);
    EXPECT_LT(err.tail<3>().norm(), 0.01);
    EXPECT_LT(err.head<3>().norm() * 180.0 / M_PI, 0.05);
  }
}

}  // namespace
}  // namespace plucker
