// Runs every registered Jacobian check with 1000 seeded samples (tests of the individual modules
// add their curated cases next to their code).
#include <gtest/gtest.h>

#include <cmath>

#include "plucker/verify/jacobian_check.h"

namespace plucker {
namespace verify {
namespace {

class AllChecks : public ::testing::TestWithParam<NamedJacobianCheck> {};

TEST_P(AllChecks, AnalyticMatchesAutodiffAndCentralDifferences) {
  JacobianCheckOptions options;
  options.samples = 1000;
  options.seed = 20261122;
  const JacobianCheckRun run = RunJacobianChecks({GetParam()}, GetParam().name, 1, options);
  EXPECT_TRUE(run.ok()) << run.error;
}

INSTANTIATE_TEST_SUITE_P(Registry, AllChecks, ::testing::ValuesIn(AllJacobianChecks()),
                         [](const auto& info) {
                           std::string n = info.param.name;
                           for (char& c : n)
                             if (!isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });

// The parameterised test above runs whatever the registry holds; this pins how much that is.
TEST(Registry, HoldsEveryCheck) {
  EXPECT_EQ(GeometryJacobianChecks().size(), 15u);
  EXPECT_EQ(FactorJacobianChecks().size(), 18u);
  EXPECT_EQ(AllJacobianChecks().size(), 33u);
}

// Ridders' differences against the exact derivative of a function that varies on a scale of
// 1e-3 (a far line's angle varies on 1e-6): a fixed 1e-6 step is limited by truncation there.
TEST(RiddersJacobian, BeatsFixedStepCentralDifferencesWhereCurvatureIsHigh) {
  const auto f = [](const Eigen::VectorXd& x) {
    return Eigen::VectorXd::Constant(1, std::sin(1e3 * x(0)) * x(1));
  };
  const Eigen::Vector2d x(0.3, -0.2);
  const Eigen::RowVector2d exact(1e3 * std::cos(1e3 * x(0)) * x(1), std::sin(1e3 * x(0)));
  const double ridders = (RiddersJacobian(f, x, 1e-4) - exact).norm() / exact.norm();
  const double fixed = (NumericJacobian(f, x, 1e-6) - exact).norm() / exact.norm();
  EXPECT_LT(ridders, 1e-10);
  EXPECT_GT(fixed, 1e-8);  // the case is hard for a fixed step
}

// A test of the tests: a misspelled filter (the defect of issue 7: "LineReprojection" for
// "factor.line.Reprojection") or a wrong count fails, and the error says why.
TEST(RunJacobianChecks, FailsOnEmptyOrUnexpectedSelection) {
  JacobianCheckOptions options;
  options.samples = 10;
  const JacobianCheckRun misspelled =
      RunJacobianChecks(FactorJacobianChecks(), "LineReprojection", 4, options);
  EXPECT_FALSE(misspelled.ok());
  EXPECT_TRUE(misspelled.stats.empty());
  EXPECT_NE(misspelled.error.find("selected 0 checks, expected 4"), std::string::npos)
      << misspelled.error;
  const JacobianCheckRun too_many =
      RunJacobianChecks(FactorJacobianChecks(), "factor.line.", 2, options);
  EXPECT_FALSE(too_many.ok());
  EXPECT_EQ(too_many.stats.size(), 8u);  // four reprojection, two anchored, time offset, stereo
  const JacobianCheckRun exact =
      RunJacobianChecks(FactorJacobianChecks(), "factor.line.", 8, options);
  EXPECT_TRUE(exact.ok()) << exact.error;
}

// A selected check that does not reach the requested sample count, or fails, fails the run.
TEST(RunJacobianChecks, FailsOnTooFewSamplesOrAFailingCheck) {
  const auto fake = [](int samples, int failures) {
    return NamedJacobianCheck{"fake", [=](const JacobianCheckOptions&) {
                                JacobianCheckStats s;
                                s.name = "fake";
                                s.samples = samples;
                                s.failures = failures;
                                s.first_failure = failures ? "fake sample 1: too far" : "";
                                return s;
                              }};
  };
  JacobianCheckOptions options;
  options.samples = 100;
  EXPECT_TRUE(RunJacobianChecks({fake(100, 0)}, "fake", 1, options).ok());
  const JacobianCheckRun few = RunJacobianChecks({fake(99, 0)}, "fake", 1, options);
  EXPECT_NE(few.error.find("99 samples, expected >= 100"), std::string::npos) << few.error;
  const JacobianCheckRun failing = RunJacobianChecks({fake(100, 1)}, "fake", 1, options);
  EXPECT_NE(failing.error.find("too far"), std::string::npos) << failing.error;
}

TEST(JacobianError, RelativeAboveOneAbsoluteBelow) {
  Eigen::MatrixXd a(1, 1), b(1, 1);
  a << 101.0;
  b << 100.0;
  EXPECT_NEAR(JacobianError(a, b), 0.01, 1e-15);
  a << 0.5;
  b << 0.25;
  EXPECT_NEAR(JacobianError(a, b), 0.25, 1e-15);
  a << std::nan("");
  EXPECT_TRUE(std::isinf(JacobianError(a, b)));
}

}  // namespace
}  // namespace verify
}  // namespace plucker
