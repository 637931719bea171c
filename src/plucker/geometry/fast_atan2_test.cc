#include "plucker/geometry/fast_atan2.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace plucker {
namespace {

TEST(FastAtan2Test, MaxErrorOverTheCircle) {
  double max_error = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const double angle = -M_PI + 2.0 * M_PI * i / 200000.0;
    for (const double r : {1e-3, 1.0, 80.0}) {
      const double y = r * std::sin(angle), x = r * std::cos(angle);
      max_error = std::max(max_error, std::abs(FastAtan2(y, x) - std::atan2(y, x)));
    }
  }
  EXPECT_LT(max_error, 2e-6);
}

TEST(FastAtan2Test, AxesAndSpecialValues) {
  EXPECT_EQ(FastAtan2(0.0, 0.0), 0.0);
  EXPECT_NEAR(FastAtan2(0.0, 1.0), 0.0, 1e-12);
  EXPECT_NEAR(FastAtan2(1.0, 0.0), M_PI / 2, 1e-12);
  EXPECT_NEAR(FastAtan2(-1.0, 0.0), -M_PI / 2, 1e-12);
  EXPECT_NEAR(FastAtan2(0.0, -1.0), M_PI, 1e-12);
  EXPECT_NEAR(FastAtan2(1.0, 1.0), M_PI / 4, 2e-6);
  EXPECT_NEAR(FastAtan2(-1.0, -1.0), -3 * M_PI / 4, 2e-6);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(FastAtan2(nan, 1.0)));
  EXPECT_TRUE(std::isnan(FastAtan2(1.0, nan)));
  EXPECT_TRUE(std::isnan(FastAtan2(0.0, nan)));
}

}  // namespace

}  // namespace plucker
