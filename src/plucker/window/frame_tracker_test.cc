#include "plucker/window/frame_tracker.h"

#include <ceres/autodiff_cost_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <stdexcept>

#include "plucker/factors/anchored_line_factor.h"
#include "plucker/factors/held_extrinsic_factor.h"
#include "plucker/factors/point_reprojection_factor.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/geometry/orthonormal_line.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace window {
namespace {

const PinholeIntrinsics kK{400.0, 400.0, 319.5, 239.5};

Eigen::Vector2d Project(const SE3d& T_w_c, const Eigen::Vector3d& p_w) {
  const Eigen::Vector3d p = T_w_c.Inverse() * p_w;
  return Eigen::Vector2d(kK.fx * p.x() / p.z() + kK.cx, kK.fy * p.y() / p.z() + kK.cy);
}

// A body pose seen through an extrinsic: 80 points and 12 anchored lines in front of the
// camera, 1 px noise, every tenth point 30 px off (outliers the robust loss must downweight).
struct Scene {
  SE3d T_w_b, T_b_c;
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<double, 6>> lines;  // anchored orthonormal blocks
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  std::vector<PoseTerm> terms;
  int outliers = 0;

  explicit Scene(std::uint64_t seed) {
    verify::Rng rng(seed);
    std::normal_distribution<double> noise(0.0, 1.0);
    T_w_b = verify::RandomPose(rng);
    T_b_c = verify::RandomPose(rng, 0.2);
    const SE3d T_w_c = T_w_b * T_b_c;
    points.reserve(80);
    for (int i = 0; i < 80; ++i) {
      const Eigen::Vector3d p_c(verify::Uniform(rng, -3, 3), verify::Uniform(rng, -2, 2),
                                verify::Uniform(rng, 3, 12));
      points.push_back(T_w_c * p_c);
      Eigen::Vector2d uv = Project(T_w_c, points.back()) + Eigen::Vector2d(noise(rng), noise(rng));
      if (i % 10 == 0) {
        uv += Eigen::Vector2d(30.0, -20.0);
        ++outliers;
      }
      costs.emplace_back(new HeldExtrinsicFactor<3>(
          PointReprojectionFactorVI::Create(kK, uv, Eigen::Matrix2d::Identity()), T_b_c));
    }
    lines.reserve(12);
    for (int i = 0; i < 12; ++i) {
      const Eigen::Vector3d a =
          T_w_c * Eigen::Vector3d(verify::Uniform(rng, -3, 3), verify::Uniform(rng, -2, 2),
                                  verify::Uniform(rng, 4, 10));
      const Eigen::Vector3d b = a + T_w_c.RotationMatrix() * verify::RandomVector(rng, 1.5);
      if ((T_w_c.Inverse() * b).z() < 1.0) continue;
      const Line6d L_w = LineFromPoints<double>(a, b);
      const LineAnchor anchor = MakeLineAnchor(L_w, T_w_c.translation());
      std::array<double, 6> block;
      OrthonormalFromPlucker(AnchoredFromWorld(L_w, anchor))->ToParameters(block.data());
      lines.push_back(block);
      const Eigen::Vector2d s = Project(T_w_c, a) + Eigen::Vector2d(noise(rng), noise(rng));
      const Eigen::Vector2d e = Project(T_w_c, b) + Eigen::Vector2d(noise(rng), noise(rng));
      costs.emplace_back(new HeldExtrinsicFactor<6>(
          AnchoredLineFactorVI::Create(kK, s, e, Eigen::Matrix2d::Identity(), anchor), T_b_c));
    }
    for (std::size_t i = 0; i < costs.size(); ++i) {
      terms.push_back(
          {costs[i].get(), i < points.size() ? points[i].data() : lines[i - points.size()].data()});
    }
  }
};

// The same terms solved by Ceres (DENSE_QR, the pose on the PoseManifold): the observations with
// `loss`, a pose-only term (no landmark) without a loss, as RefinePose treats them.
SE3d SolveWithCeres(const std::vector<PoseTerm>& terms, const ceres::LossFunction* loss,
                    const SE3d& start, double* final_cost) {
  double pose[7];
  start.ToParameters(pose);
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  for (const PoseTerm& t : terms) {
    auto* cost = const_cast<ceres::CostFunction*>(t.cost);
    if (t.landmark == nullptr) {
      problem.AddResidualBlock(cost, nullptr, pose);
      continue;
    }
    double* landmark = const_cast<double*>(t.landmark);
    problem.AddResidualBlock(cost, const_cast<ceres::LossFunction*>(loss), pose, landmark);
    problem.SetParameterBlockConstant(landmark);
  }
  problem.SetManifold(pose, new PoseManifold);
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = 100;
  so.function_tolerance = so.gradient_tolerance = so.parameter_tolerance = 1e-14;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  *final_cost = summary.final_cost;
  return SE3d::FromParameters(pose);
}

// From a start 0.1 rad and 0.2 m off, the refinement reaches Ceres' minimum of the same robust
// cost (points and lines, a held extrinsic) and its cost, over 20 random scenes.
TEST(RefinePose, ReachesTheMinimumCeresFindsOnTheSameRobustCost) {
  const ceres::HuberLoss loss(1.5);
  int checked = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const Scene s(seed);
    ASSERT_GE(s.terms.size(), 85u);
    Vector6d d;
    d << 0.06, -0.05, 0.06, 0.12, -0.1, 0.13;
    const SE3d start = s.T_w_b.Plus(d);
    double ceres_cost = 0.0;
    const SE3d ceres_pose = SolveWithCeres(s.terms, &loss, start, &ceres_cost);
    PoseRefinementOptions options;
    options.max_iterations = 100;
    options.function_tolerance = options.gradient_tolerance = options.parameter_tolerance = 1e-14;
    double pose[7];
    start.ToParameters(pose);
    const PoseRefinementSummary summary = RefinePose(s.terms, &loss, options, pose);
    ASSERT_TRUE(summary.ok);
    EXPECT_GT(summary.iterations, 1);
    EXPECT_GT(summary.initial_cost, 5.0 * summary.final_cost) << "seed " << seed;
    EXPECT_NEAR(summary.final_cost, ceres_cost, 1e-9 * ceres_cost) << "seed " << seed;
    EXPECT_LT(SE3d::FromParameters(pose).Minus(ceres_pose).norm(), 1e-7) << "seed " << seed;
    // The outliers did not pull it: within a few cm and mrad of the truth.
    EXPECT_LT(SE3d::FromParameters(pose).Minus(s.T_w_b).norm(), 0.05) << "seed " << seed;
    ++checked;
  }
  EXPECT_EQ(checked, 20);
}

// The default budget (8 iterations, Ceres' default tolerances) from the same start: close to the
// converged minimum, cost within 1e-4 of it.
TEST(RefinePose, DefaultToleranceStopsNearTheMinimum) {
  const ceres::HuberLoss loss(1.5);
  const Scene s(5);
  Vector6d d;
  d << 0.01, -0.01, 0.01, 0.02, -0.02, 0.02;
  const SE3d start = s.T_w_b.Plus(d);
  double ceres_cost = 0.0;
  const SE3d ceres_pose = SolveWithCeres(s.terms, &loss, start, &ceres_cost);
  double pose[7];
  start.ToParameters(pose);
  const PoseRefinementSummary summary = RefinePose(s.terms, &loss, {}, pose);
  ASSERT_TRUE(summary.ok);
  EXPECT_LE(summary.iterations, 8);
  EXPECT_NEAR(summary.final_cost, ceres_cost, 1e-4 * ceres_cost);
  EXPECT_LT(SE3d::FromParameters(pose).Minus(ceres_pose).norm(), 1e-3);
}

// Without a loss, the plain least-squares minimum (the outliers pull it: not the truth).
TEST(RefinePose, WithoutALossIsPlainLeastSquares) {
  const Scene s(9);
  const SE3d start = s.T_w_b;
  double ceres_cost = 0.0;
  const SE3d ceres_pose = SolveWithCeres(s.terms, nullptr, start, &ceres_cost);
  PoseRefinementOptions options;
  options.max_iterations = 100;
  options.function_tolerance = options.gradient_tolerance = options.parameter_tolerance = 1e-14;
  double pose[7];
  start.ToParameters(pose);
  const PoseRefinementSummary summary = RefinePose(s.terms, nullptr, options, pose);
  ASSERT_TRUE(summary.ok);
  EXPECT_NEAR(summary.final_cost, ceres_cost, 1e-9 * ceres_cost);
  EXPECT_LT(SE3d::FromParameters(pose).Minus(ceres_pose).norm(), 1e-8);
}

// r = S Minus(T_w_b, prior) (PoseManifold tangent), the kind of pose-only term the visual-inertial
// tracking adds for the IMU prediction.
struct PosePrior {
  SE3d prior;
  Vector6d inverse_sigma;
  template <typename T>
  bool operator()(const T* x, T* residual) const {
    const SE3<T> X = SE3<T>::FromParameters(x);
    const Eigen::Quaternion<T> dq = prior.rotation().cast<T>().conjugate() * X.rotation();
    Eigen::Matrix<T, 6, 1> d;
    d.template head<3>() = LogUnitQuaternion<T>(dq);
    d.template tail<3>() = X.translation() - prior.translation().cast<T>();
    for (int i = 0; i < 6; ++i) residual[i] = T(inverse_sigma(i)) * d(i);
    return true;
  }
};

// With a pose-only prior term (6 residuals, no landmark, no robust loss) among the observations:
// the minimum and cost Ceres finds for the same problem (the prior as a residual block without
// loss), over 10 random scenes; the prior (5 cm and 0.02 rad off the truth, sigmas 1 cm and 5
// mrad) moved the pose away from the vision-only minimum, towards itself.
TEST(RefinePose, APosePriorTermMatchesCeresWithTheSamePrior) {
  const ceres::HuberLoss loss(1.5);
  PoseRefinementOptions options;
  options.max_iterations = 100;
  options.function_tolerance = options.gradient_tolerance = options.parameter_tolerance = 1e-14;
  int checked = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const Scene s(seed);
    Vector6d off, inverse_sigma;
    off << 0.02, -0.01, 0.015, 0.05, 0.03, -0.04;
    inverse_sigma << Eigen::Vector3d::Constant(200.0), Eigen::Vector3d::Constant(100.0);
    const SE3d prior_pose = s.T_w_b.Plus(off);
    ceres::AutoDiffCostFunction<PosePrior, 6, 7> prior(new PosePrior{prior_pose, inverse_sigma});
    std::vector<PoseTerm> terms = s.terms;
    terms.push_back({&prior, nullptr});
    Vector6d d;
    d << 0.03, -0.02, 0.03, 0.06, -0.05, 0.07;
    const SE3d start = s.T_w_b.Plus(d);
    // Ceres: the observations (Huber) and the prior (no loss).
    double ceres_cost = 0.0;
    const SE3d ceres_pose = SolveWithCeres(terms, &loss, start, &ceres_cost);
    double pose[7];
    // This refinement, with and without the prior.
    start.ToParameters(pose);
    const PoseRefinementSummary with_prior = RefinePose(terms, &loss, options, pose);
    ASSERT_TRUE(with_prior.ok);
    const SE3d refined = SE3d::FromParameters(pose);
    start.ToParameters(pose);
    ASSERT_TRUE(RefinePose(s.terms, &loss, options, pose).ok);
    const SE3d vision_only = SE3d::FromParameters(pose);
    EXPECT_NEAR(with_prior.final_cost, ceres_cost, 1e-9 * ceres_cost) << "seed " << seed;
    EXPECT_LT(refined.Minus(ceres_pose).norm(), 1e-7) << "seed " << seed;
    EXPECT_GT(refined.Minus(vision_only).norm(), 1e-3) << "seed " << seed;
    EXPECT_LT(refined.Minus(prior_pose).norm(), vision_only.Minus(prior_pose).norm())
        << "seed " << seed;
    ++checked;
  }
  EXPECT_EQ(checked, 10);
}

// A term that cannot be evaluated at the start (a point behind the camera): not ok, the pose
// unchanged. A malformed term throws.
TEST(RefinePose, RefusesTermsItCannotEvaluateAndMalformedTerms) {
  Scene s(2);
  const Eigen::Vector3d behind = s.T_w_b * s.T_b_c * Eigen::Vector3d(0, 0, -2);
  std::vector<PoseTerm> terms = s.terms;
  terms.push_back({s.terms.front().cost, behind.data()});
  double pose[7];
  s.T_w_b.ToParameters(pose);
  double before[7];
  std::copy(pose, pose + 7, before);
  const PoseRefinementSummary summary = RefinePose(terms, nullptr, {}, pose);
  EXPECT_FALSE(summary.ok);
  EXPECT_EQ(summary.iterations, 0);
  for (int i = 0; i < 7; ++i) EXPECT_EQ(pose[i], before[i]);
  terms.back().landmark = nullptr;
  EXPECT_THROW(RefinePose(terms, nullptr, {}, pose), std::invalid_argument);
  std::unique_ptr<ceres::CostFunction> vi(
      PointReprojectionFactorVI::Create(kK, Eigen::Vector2d(1, 2), Eigen::Matrix2d::Identity()));
  EXPECT_THROW(RefinePose({{vi.get(), s.points[0].data()}}, nullptr, {}, pose),
               std::invalid_argument);
  // A pose-only term needs 6 residuals on the pose alone.
  ceres::AutoDiffCostFunction<PosePrior, 6, 7> prior(new PosePrior{s.T_w_b, Vector6d::Ones()});
  EXPECT_NO_THROW(RefinePose({{&prior, nullptr}}, nullptr, {}, pose));
  EXPECT_THROW(RefinePose({{&prior, s.points[0].data()}}, nullptr, {}, pose),
               std::invalid_argument);
}

}  // namespace
}  // namespace window
}  // namespace plucker
