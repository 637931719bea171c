#include "plucker/factors/marginalization.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>

#include "plucker/verify/checks.h"
#include "plucker/verify/marginalization_problem.h"

namespace plucker {
namespace {

// H and g of the whole problem from Ceres' own evaluation (tangent Jacobian through the
// manifolds), in the order `order` of parameter blocks: independent of the prior's assembly.
void CeresNormalEquations(verify::MarginalizationProblem& p, const std::vector<double*>& order,
                          Eigen::MatrixXd* H, Eigen::VectorXd* g) {
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  for (const MarginalizationResidual& r : p.residuals) {
    problem.AddResidualBlock(const_cast<ceres::CostFunction*>(r.cost),
                             const_cast<ceres::LossFunction*>(r.loss), r.blocks);
  }
  for (const MarginalizationBlock& b : p.blocks) {
    if (b.manifold) problem.SetManifold(b.values, const_cast<ceres::Manifold*>(b.manifold));
  }
  ceres::Problem::EvaluateOptions eo;
  eo.parameter_blocks = order;
  std::vector<double> residuals;
  ceres::CRSMatrix crs;
  ASSERT_TRUE(problem.Evaluate(eo, nullptr, &residuals, nullptr, &crs));
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row)
    for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) J(row, crs.cols[k]) = crs.values[k];
  const Eigen::Map<const Eigen::VectorXd> r(residuals.data(), residuals.size());
  *H = J.transpose() * J;
  *g = J.transpose() * r;
}

// Seeds 1-5 without a loss, 6-10 with a Huber loss on every residual (Ceres' correction applies
// to both sides).
TEST(MarginalizationPrior, EqualsTheDenseSchurComplement) {
  int compared = 0, robust = 0;
  const ceres::HuberLoss huber(0.5);
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    verify::Rng rng(seed);
    auto p = verify::MakeMarginalizationProblem(rng, 3, 5, 2);
    if (seed > 5) {
      for (MarginalizationResidual& r : p->residuals) r.loss = &huber;
      ++robust;
    }
    const std::vector<double*> removed = {p->poses[0].data(), p->points[0].data()};
    // Ceres order: the removed blocks, then every other block as the prior keeps them.
    const MarginalizationPrior prior =
        MarginalizationPrior::Build(p->blocks, p->residuals, removed);
    std::vector<double*> order = removed;
    for (const MarginalizationBlock& b : prior.KeptBlocks()) order.push_back(b.values);
    ASSERT_EQ(order.size(), p->blocks.size());
    Eigen::MatrixXd H;
    Eigen::VectorXd g;
    CeresNormalEquations(*p, order, &H, &g);
    const int m = 6 + 3, k = static_cast<int>(H.rows()) - m;
    const Eigen::MatrixXd H_mm_inv = H.topLeftCorner(m, m).inverse();
    const Eigen::MatrixXd H_star =
        H.bottomRightCorner(k, k) - H.bottomLeftCorner(k, m) * H_mm_inv * H.topRightCorner(m, k);
    const Eigen::VectorXd g_star = g.tail(k) - H.bottomLeftCorner(k, m) * H_mm_inv * g.head(m);
    EXPECT_EQ(prior.Statistics().kept_dimension, k);
    EXPECT_LT((prior.Information() - H_star).norm(), 1e-9 * H_star.norm()) << "seed " << seed;
    EXPECT_LT((prior.Gradient() - g_star).norm(), 1e-9 * (1.0 + g_star.norm())) << "seed " << seed;
    ++compared;
  }
  EXPECT_EQ(compared, 10);
  EXPECT_EQ(robust, 5);
}

// A linear residual r = A [x_a; x_b] - c on 2-vectors (b optional).
class LinearCost final : public ceres::CostFunction {
 public:
  LinearCost(Eigen::MatrixXd A, Eigen::VectorXd c, int blocks)
      : A_(std::move(A)), c_(std::move(c)) {
    set_num_residuals(static_cast<int>(c_.size()));
    for (int i = 0; i < blocks; ++i) mutable_parameter_block_sizes()->push_back(2);
  }
  bool Evaluate(double const* const* x, double* r, double** J) const override {
    Eigen::VectorXd stacked(A_.cols());
    for (int b = 0; b < A_.cols() / 2; ++b)
      stacked.segment<2>(2 * b) = Eigen::Vector2d(x[b][0], x[b][1]);
    Eigen::Map<Eigen::VectorXd>(r, c_.size()) = A_ * stacked - c_;
    if (J) {
      for (int b = 0; b < A_.cols() / 2; ++b) {
        if (!J[b]) continue;
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>(J[b], c_.size(), 2) =
            A_.middleCols<2>(2 * b);
      }
    }
    return true;
  }

 private:
  Eigen::MatrixXd A_;
  Eigen::VectorXd c_;
};

// x0 - x1 - x2 - x3 chain with a prior on x0 and an absolute measurement of x3: marginalizing x0
// into a prior on x1 and solving the rest gives the batch solution exactly (linear-Gaussian).
TEST(MarginalizationPrior, MatchesTheBatchSolutionOnALinearGaussianChain) {
  verify::Rng rng(3);
  auto random = [&](int r, int c) {
    Eigen::MatrixXd M(r, c);
    for (int i = 0; i < r; ++i)
      for (int j = 0; j < c; ++j) M(i, j) = verify::Uniform(rng, -1.0, 1.0);
    return M;
  };
  std::vector<std::unique_ptr<LinearCost>> costs;
  costs.emplace_back(
      new LinearCost(random(2, 2) + 2 * Eigen::MatrixXd::Identity(2, 2), random(2, 1), 1));
  for (int i = 0; i < 3; ++i) costs.emplace_back(new LinearCost(random(3, 4), random(3, 1), 2));
  costs.emplace_back(
      new LinearCost(random(2, 2) + 2 * Eigen::MatrixXd::Identity(2, 2), random(2, 1), 1));
  auto solve = [](ceres::Problem* problem) {
    ceres::Solver::Options o;
    o.linear_solver_type = ceres::DENSE_QR;
    o.initial_trust_region_radius = 1e16;  // Gauss-Newton: one exact step on a linear problem
    o.function_tolerance = o.gradient_tolerance = o.parameter_tolerance = 1e-16;
    ceres::Solver::Summary s;
    ceres::Solve(o, problem, &s);
  };
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  double batch[4][2] = {{0, 0}, {0, 0}, {0, 0}, {0, 0}};
  {
    ceres::Problem problem(po);
    problem.AddResidualBlock(costs[0].get(), nullptr, batch[0]);
    for (int i = 0; i < 3; ++i)
      problem.AddResidualBlock(costs[1 + i].get(), nullptr, batch[i], batch[i + 1]);
    problem.AddResidualBlock(costs[4].get(), nullptr, batch[3]);
    solve(&problem);
  }
  double window[4][2] = {
      {0.3, -0.2}, {1.0, 2.0}, {-1.0, 0.5}, {0.1, 0.1}};  // any linearisation point
  const std::vector<MarginalizationBlock> blocks = {{window[0], 2, nullptr},
                                                    {window[1], 2, nullptr}};
  const MarginalizationPrior prior = MarginalizationPrior::Build(
      blocks,
      {{costs[0].get(), nullptr, {window[0]}}, {costs[1].get(), nullptr, {window[0], window[1]}}},
      {window[0]});
  ASSERT_EQ(prior.KeptBlocks().size(), 1u);
  std::unique_ptr<ceres::CostFunction> prior_cost(prior.CreateCostFunction());
  {
    ceres::Problem problem(po);
    problem.AddResidualBlock(prior_cost.get(), nullptr, window[1]);
    for (int i = 1; i < 3; ++i)
      problem.AddResidualBlock(costs[1 + i].get(), nullptr, window[i], window[i + 1]);
    problem.AddResidualBlock(costs[4].get(), nullptr, window[3]);
    solve(&problem);
  }
  for (int i = 1; i < 4; ++i) {
    EXPECT_NEAR(window[i][0], batch[i][0], 1e-9) << "x" << i;
    EXPECT_NEAR(window[i][1], batch[i][1], 1e-9) << "x" << i;
  }
}

// Nothing marginalized (the window keeps a leaving keyframe's pose for its line observations):
// the prior is the linearisation itself, H* = J^T J and g* = J^T r on the blocks (this used to
// crash on the empty eigen-decomposition).
TEST(MarginalizationPrior, NothingMarginalizedKeepsTheLinearisation) {
  Eigen::MatrixXd A(3, 4);
  A << 1, 2, 0, -1, 0, 1, 3, 1, 2, 0, 1, 1;
  const Eigen::Vector3d c(0.5, -1.0, 2.0);
  LinearCost cost(A, c, 2);
  double a[2] = {0.3, -0.2}, b[2] = {1.0, 2.0};
  const MarginalizationPrior prior = MarginalizationPrior::Build({{a, 2, nullptr}, {b, 2, nullptr}},
                                                                 {{&cost, nullptr, {a, b}}}, {});
  ASSERT_EQ(prior.KeptBlocks().size(), 2u);
  EXPECT_EQ(prior.Statistics().marginalized_dimension, 0);
  EXPECT_EQ(prior.Statistics().prior_rank, 3);
  const Eigen::Vector4d x(a[0], a[1], b[0], b[1]);
  const Eigen::Vector3d r = A * x - c;
  EXPECT_LT((prior.Information() - A.transpose() * A).norm(), 1e-9);
  EXPECT_LT((prior.Gradient() - A.transpose() * r).norm(), 1e-9);
}

// Lines seen by the removed camera keep their information in the prior (PL-VIO drops them).
TEST(MarginalizationPrior, KeepsTheInformationOfLinesSeenByTheRemovedCamera) {
  verify::Rng rng(9);
  auto p = verify::MakeMarginalizationProblem(rng, 3, 5, 2);
  const std::vector<double*> removed = {p->poses[0].data()};
  const MarginalizationPrior prior =
      MarginalizationPrior::Build(p->blocks, p->ResidualsOf(removed), removed);
  // Kept: the 5 points and 2 lines the camera saw (no other camera shares a residual with it).
  ASSERT_EQ(prior.KeptBlocks().size(), 7u);
  const Eigen::MatrixXd H = prior.Information();
  int line_blocks = 0;
  for (int b = 0, col = 0; b < 7; ++b) {
    const int t =
        prior.KeptBlocks()[b].manifold ? prior.KeptBlocks()[b].manifold->TangentSize() : 3;
    if (prior.KeptBlocks()[b].ambient_size == 6) {
      EXPECT_GT(H.block(col, col, t, t).norm(), 1.0) << "line block " << b;
      ++line_blocks;
    }
    col += t;
  }
  EXPECT_EQ(line_blocks, 2);
}

TEST(MarginalizationPrior, JacobianChecksPass) {
  verify::JacobianCheckOptions options;
  options.samples = 100;
  const verify::JacobianCheckRun run = verify::RunJacobianChecks(
      verify::MarginalizationJacobianChecks(), "factor.marginalization.", 1, options);
  EXPECT_TRUE(run.ok()) << run.error;
}

TEST(MarginalizationPrior, RefusesBadInput) {
  verify::Rng rng(1);
  auto p = verify::MakeMarginalizationProblem(rng, 2, 2, 1);
  double stray[3] = {0, 0, 0};
  EXPECT_THROW(MarginalizationPrior::Build(p->blocks, p->residuals, {stray}),
               std::invalid_argument);
  std::vector<MarginalizationBlock> blocks = p->blocks;
  blocks.pop_back();  // a residual now references an undeclared line block
  EXPECT_THROW(MarginalizationPrior::Build(blocks, p->residuals, {p->poses[0].data()}),
               std::invalid_argument);
  ceres::QuaternionManifold quaternion;
  blocks = p->blocks;
  blocks[0].manifold = &quaternion;
  EXPECT_THROW(MarginalizationPrior::Build(blocks, p->residuals, {p->poses[0].data()}),
               std::invalid_argument);
  EXPECT_THROW(MarginalizationPrior::Build(p->blocks, {}, {p->poses[0].data()}),
               std::invalid_argument);
}

TEST(MarginalizationPrior, MarginalizingEveryBlockGivesAnEmptyPrior) {
  verify::Rng rng(2);
  auto p = verify::MakeMarginalizationProblem(rng, 2, 3, 2);
  std::vector<double*> all;
  int dimension = 0;
  for (const MarginalizationBlock& b : p->blocks) {
    all.push_back(b.values);
    dimension += b.manifold ? b.manifold->TangentSize() : b.ambient_size;
  }
  ASSERT_EQ(all.size(), 7u);
  const MarginalizationPrior prior = MarginalizationPrior::Build(p->blocks, p->residuals, all);
  EXPECT_TRUE(prior.KeptBlocks().empty());
  EXPECT_EQ(prior.Statistics().prior_rank, 0);
  EXPECT_EQ(prior.Statistics().kept_dimension, 0);
  EXPECT_EQ(prior.Statistics().marginalized_dimension, dimension);
  EXPECT_EQ(prior.Residual().size(), 0);
  EXPECT_THROW(std::unique_ptr<ceres::CostFunction>(prior.CreateCostFunction()), std::logic_error);
  EXPECT_THROW(std::unique_ptr<ceres::CostFunction>(prior.CreateAutoDiffCostFunction()),
               std::logic_error);
}

}  // namespace
}  // namespace plucker
