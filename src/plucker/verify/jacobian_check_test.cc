// Runs every registered Jacobian check with 1000 seeded samples (tests of the individual modules
// add their curated cases next to their code).
#include <gtest/gtest.h>

#include "plucker/verify/jacobian_check.h"

namespace plucker {
namespace verify {
namespace {

class AllChecks : public ::testing::TestWithParam<NamedJacobianCheck> {};

TEST_P(AllChecks, AnalyticMatchesAutodiffAndCentralDifferences) {
  JacobianCheckOptions options;
  options.samples = 1000;
  options.seed = 20261122;
  const JacobianCheckStats s = GetParam().run(options);
  EXPECT_GE(s.samples, 1000) << s.name;
  EXPECT_TRUE(s.passed()) << s.first_failure;
  EXPECT_LE(s.worst_autodiff, 1e-9) << s.name;
  EXPECT_LE(s.worst_numeric, 1e-6) << s.name;
}

INSTANTIATE_TEST_SUITE_P(Registry, AllChecks, ::testing::ValuesIn(AllJacobianChecks()),
                         [](const auto& info) {
                           std::string n = info.param.name;
                           for (char& c : n)
                             if (!isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });

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
