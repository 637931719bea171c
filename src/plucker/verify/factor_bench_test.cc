#include "plucker/verify/factor_bench.h"

#include <gtest/gtest.h>

#include <cmath>

namespace plucker {
namespace verify {
namespace {

TEST(FactorBench, EveryInputEvaluatesWithBothVersions) {
  const std::vector<FactorBenchCase> cases = MakeFactorBenchCases(3);
  ASSERT_EQ(cases.size(), 9u);
  for (const FactorBenchCase& c : cases) {
    ASSERT_EQ(c.analytic.size(), static_cast<size_t>(kFactorBenchInputs)) << c.name;
    ASSERT_EQ(c.autodiff.size(), c.analytic.size()) << c.name;
    FactorBenchBuffers an(*c.analytic.front()), ad(*c.autodiff.front());
    for (int i = 0; i < kFactorBenchInputs; ++i) {
      ASSERT_TRUE(EvaluateFactorBenchCase(c, true, i, &an)) << c.name << " input " << i;
      ASSERT_TRUE(EvaluateFactorBenchCase(c, false, i, &ad)) << c.name << " input " << i;
      EXPECT_NEAR(an.Checksum(), ad.Checksum(), 1e-9 * (1.0 + std::abs(ad.Checksum())))
          << c.name << " input " << i;
    }
  }
}

TEST(FactorBench, ReturnsOneFiniteRowPerFactor) {
  // A smoke test only: performance targets are reported by `plucker bench factors`, not asserted.
  const std::vector<FactorBenchRow> rows = BenchmarkFactors(500, 4);
  ASSERT_EQ(rows.size(), 9u);
  for (const FactorBenchRow& r : rows) {
    EXPECT_FALSE(r.name.empty());
    EXPECT_GT(r.analytic_ns, 0.0) << r.name;
    EXPECT_GT(r.autodiff_ns, 0.0) << r.name;
    EXPECT_TRUE(std::isfinite(r.ratio)) << r.name;
    EXPECT_GT(r.flops_estimate, 0.0) << r.name;
  }
}

}  // namespace
}  // namespace verify
}  // namespace plucker
