#include "plucker/lidar/pose_solver.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "plucker/factors/lidar_factors.h"
#include "plucker/factors/pose_manifold.h"

namespace plucker {
namespace lidar {
namespace {

// The same residuals as the solver's values and as the factors (for ceres::Solve and Evaluate).
struct Residuals {
  LidarResiduals values;
  std::vector<std::unique_ptr<ceres::CostFunction>> factors;
  void AddPlane(const Eigen::Vector3d& p_s, const Eigen::Vector3d& m_w, const Eigen::Vector3d& q_w,
                double sigma) {
    values.planes.push_back(PlaneResidual::Create(p_s, m_w, q_w, sigma));
    factors.emplace_back(PointToPlaneFactor::Create(p_s, m_w, q_w, sigma));
  }
  void AddEdge(const Eigen::Vector3d& p_s, const Eigen::Vector3d& a_w, const Eigen::Vector3d& u_w,
               double sigma) {
    values.edges.push_back(EdgeResidual::CreateFromDirection(p_s, a_w, u_w, sigma));
    factors.emplace_back(PointToEdgeFactor::CreateFromDirection(p_s, a_w, u_w, sigma));
  }
};

// Plane and edge correspondences of scan points seen from T_w_s_gt: points on six planes of
// different orientations and on four lines, with range noise and a share of gross outliers.
Residuals MakeProblem(const SE3d& T_w_s_gt, double noise, double outlier_share, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> n(0.0, 1.0);
  Residuals residuals;
  const SE3d T_s_w = T_w_s_gt.Inverse();
  for (int i = 0; i < 600; ++i) {
    const Eigen::Vector3d m_w =
        Eigen::Vector3d(u(*rng), u(*rng), 0.3 + std::abs(u(*rng))).normalized() *
        (i % 2 ? 1.0 : -1.0);
    const Eigen::Vector3d q_w(10 * u(*rng), 10 * u(*rng), u(*rng));
    Eigen::Vector3d tangent = m_w.unitOrthogonal();
    Eigen::Vector3d p_w = q_w + 3 * u(*rng) * tangent + 3 * u(*rng) * m_w.cross(tangent);
    p_w += noise * n(*rng) * m_w;
    if (u(*rng) < 2 * outlier_share - 1) p_w += 2.0 * Eigen::Vector3d(u(*rng), u(*rng), u(*rng));
    residuals.AddPlane(T_s_w * p_w, m_w, q_w, 0.05);
  }
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d a_w(10 * u(*rng), 10 * u(*rng), u(*rng));
    const Eigen::Vector3d dir = Eigen::Vector3d(u(*rng), u(*rng), u(*rng)).normalized();
    Eigen::Vector3d p_w = a_w + 2 * u(*rng) * dir + noise * Eigen::Vector3d(n(*rng), n(*rng), 0);
    residuals.AddEdge(T_s_w * p_w, a_w, dir, 0.2);
  }
  return residuals;
}

SE3d Perturb(const SE3d& T, double rotation_rad, double translation_m, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Vector3d w = Eigen::Vector3d(u(*rng), u(*rng), u(*rng)).normalized();
  const Eigen::Vector3d t = Eigen::Vector3d(u(*rng), u(*rng), u(*rng)).normalized();
  Vector6d delta;
  delta << rotation_rad * w, translation_m * t;
  return T.Plus(delta);
}

TEST(PoseSolverTest, ConvergesToTheTruePoseWithoutNoise) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    const SE3d T_w_s_gt = Perturb(SE3d(), 0.5, 3.0, &rng);
    const Residuals residuals = MakeProblem(T_w_s_gt, 0.0, 0.0, &rng);
    SE3d T = Perturb(T_w_s_gt, 5.0 * M_PI / 180.0, 0.5, &rng);
    PoseSolverOptions options;
    options.max_iterations = 30;
    options.function_tolerance = 0.0;
    options.step_tolerance = 1e-12;
    const PoseSolverSummary summary = SolvePose(residuals.values, nullptr, options, &T);
    ASSERT_TRUE(summary.usable) << summary.message;
    EXPECT_LT(T.Minus(T_w_s_gt).norm(), 1e-8) << "trial " << trial;
    EXPECT_LT(summary.final_cost, 1e-12);
    EXPECT_GT(summary.initial_cost, summary.final_cost);
  }
}

// The same cost functions and loss solved by ceres::Solve on the PoseManifold reach the same
// minimum (the loop is a faster route to Ceres' answer, not a different estimator).
TEST(PoseSolverTest, MatchesCeresSolveWithRobustLoss) {
  std::mt19937 rng(5);
  for (const bool cauchy : {false, true}) {
    for (int trial = 0; trial < 5; ++trial) {
      const SE3d T_w_s_gt = Perturb(SE3d(), 0.3, 2.0, &rng);
      const Residuals residuals = MakeProblem(T_w_s_gt, 0.02, 0.1, &rng);
      const SE3d T0 = Perturb(T_w_s_gt, 2.0 * M_PI / 180.0, 0.2, &rng);
      std::unique_ptr<ceres::LossFunction> loss;
      if (cauchy)
        loss = std::make_unique<ceres::CauchyLoss>(2.0);
      else
        loss = std::make_unique<ceres::HuberLoss>(2.0);

      SE3d T = T0;
      PoseSolverOptions options;
      options.max_iterations = 100;
      options.function_tolerance = 1e-15;
      options.step_tolerance = 1e-14;
      const PoseSolverSummary summary = SolvePose(residuals.values, loss.get(), options, &T);
      ASSERT_TRUE(summary.usable) << summary.message;

      double x[7];
      T0.ToParameters(x);
      ceres::Problem::Options problem_options;
      problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
      problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
      problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
      ceres::Problem problem(problem_options);
      PoseManifold manifold;
      problem.AddParameterBlock(x, 7);
      problem.SetManifold(x, &manifold);
      for (const auto& f : residuals.factors) problem.AddResidualBlock(f.get(), loss.get(), x);
      ceres::Solver::Options solver_options;
      solver_options.linear_solver_type = ceres::DENSE_QR;
      solver_options.max_num_iterations = 200;
      solver_options.function_tolerance = 1e-16;
      solver_options.gradient_tolerance = 1e-16;
      solver_options.parameter_tolerance = 1e-14;
      ceres::Solver::Summary ceres_summary;
      ceres::Solve(solver_options, &problem, &ceres_summary);
      const SE3d T_ceres = SE3d::FromParameters(x);

      EXPECT_LT(T.Minus(T_ceres).norm(), 1e-6) << (cauchy ? "cauchy" : "huber") << " " << trial;
      EXPECT_NEAR(summary.final_cost, ceres_summary.final_cost,
                  1e-9 * (1.0 + ceres_summary.final_cost));
      EXPECT_LT(T.Minus(T_w_s_gt).norm(), 0.02);  // and it is close to the truth
    }
  }
}

TEST(PoseSolverTest, AllPlanesParallelLeavesTheUnobservedDirectionsAlone) {
  // Every plane is z = 0: only z, roll and pitch are observed.
  Residuals residuals;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  for (int i = 0; i < 200; ++i)
    residuals.AddPlane(Eigen::Vector3d(u(rng), u(rng), -0.3), Eigen::Vector3d::UnitZ(),
                       Eigen::Vector3d::Zero(), 0.05);
  SE3d T(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1.0, 2.0, 0.0));
  const PoseSolverSummary summary = SolvePose(residuals.values, nullptr, PoseSolverOptions(), &T);
  ASSERT_TRUE(summary.usable) << summary.message;
  EXPECT_NEAR(T.translation().z(), 0.3, 1e-6);
  EXPECT_NEAR(T.translation().x(), 1.0, 1e-6);
  EXPECT_NEAR(T.translation().y(), 2.0, 1e-6);
  EXPECT_TRUE(T.rotation().coeffs().allFinite());
}

// The normal equations are formed from the residuals' tangent Jacobians: compare H = J^T J and
// g = J^T r with central differences of the factors' residuals through SE3d::Plus (the tangent
// that SolvePose steps in).
TEST(PoseSolverTest, NormalEquationsMatchCentralDifferences) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  int compared = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const SE3d T(ExpSO3<double>(Eigen::Vector3d(u(rng), u(rng), u(rng))),
                 Eigen::Vector3d(5 * u(rng), 5 * u(rng), u(rng)));
    const Eigen::Vector3d p_s(10 * u(rng), 10 * u(rng), 2 * u(rng)), q(u(rng), u(rng), u(rng));
    const Eigen::Vector3d m = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    for (const bool edge : {false, true}) {
      Residuals residuals;
      if (edge) residuals.AddEdge(p_s, q, m, 0.05);
      if (!edge) residuals.AddPlane(p_s, m, q, 0.05);
      const auto& factor = residuals.factors[0];
      auto r = [&](const SE3d& X) -> Eigen::VectorXd {
        double x[7];
        X.ToParameters(x);
        const double* parameters[1] = {x};
        Eigen::VectorXd v(factor->num_residuals());
        EXPECT_TRUE(factor->Evaluate(parameters, v.data(), nullptr));
        return v;
      };
      Eigen::MatrixXd J(factor->num_residuals(), 6);
      const double h = 1e-6;
      for (int k = 0; k < 6; ++k) {
        Vector6d d = Vector6d::Zero();
        d(k) = h;
        J.col(k) = (r(T.Plus(d)) - r(T.Plus(-d))) / (2 * h);
      }
      NormalEquations eq;
      ASSERT_TRUE(EvaluateNormalEquations(residuals.values, nullptr, T, &eq));
      const Matrix6d H = J.transpose() * J;
      const Vector6d g = J.transpose() * r(T);
      EXPECT_LT((eq.H - H).norm(), 1e-5 * (1 + H.norm()));
      EXPECT_LT((eq.g - g).norm(), 1e-5 * (1 + g.norm()));
      EXPECT_NEAR(eq.cost, 0.5 * r(T).squaredNorm(), 1e-9 * (1 + eq.cost));
      EXPECT_EQ(eq.num_residuals, edge ? 3 : 1);
      ++compared;
    }
  }
  EXPECT_EQ(compared, 100);
}

// The summary's normal equations are those of the returned pose, with its robust weights.
TEST(PoseSolverTest, SummaryHoldsTheNormalEquationsAtTheSolution) {
  std::mt19937 rng(13);
  const SE3d T_w_s_gt = Perturb(SE3d(), 0.3, 2.0, &rng);
  const Residuals residuals = MakeProblem(T_w_s_gt, 0.02, 0.1, &rng);
  const ceres::HuberLoss loss(2.0);
  for (const int iterations : {1, 2, 4, 10}) {
    SE3d T = Perturb(T_w_s_gt, 2.0 * M_PI / 180.0, 0.3, &rng);
    PoseSolverOptions options;
    options.max_iterations = iterations;
    const PoseSolverSummary summary = SolvePose(residuals.values, &loss, options, &T);
    ASSERT_TRUE(summary.usable) << summary.message;
    NormalEquations at_solution;
    ASSERT_TRUE(EvaluateNormalEquations(residuals.values, &loss, T, &at_solution));
    EXPECT_EQ((summary.normal_equations.H - at_solution.H).norm(), 0.0) << iterations;
    EXPECT_EQ(summary.normal_equations.cost, summary.final_cost);
    EXPECT_EQ(summary.normal_equations.num_residuals, 600 + 3 * 200);
  }
}

TEST(PoseSolverTest, BadInputIsReportedNotSolved) {
  Residuals none;
  SE3d T;
  PoseSolverSummary summary = SolvePose(none.values, nullptr, PoseSolverOptions(), &T);
  EXPECT_FALSE(summary.usable);
  EXPECT_EQ(summary.message, "no residuals");

  Residuals one;
  one.AddPlane(Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), 1.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  SE3d T_nan(Eigen::Quaterniond::Identity(), Eigen::Vector3d(nan, 0, 0));
  summary = SolvePose(one.values, nullptr, PoseSolverOptions(), &T_nan);
  EXPECT_FALSE(summary.usable);
  EXPECT_FALSE(summary.message.empty());
}

}  // namespace
}  // namespace lidar
}  // namespace plucker
