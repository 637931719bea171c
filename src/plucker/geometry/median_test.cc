// The two medians of geometry/median.h, and Hat of geometry/so3.h (the one skew-symmetric matrix).
#include "plucker/geometry/median.h"

#include <gtest/gtest.h>

#include <Eigen/Core>

#include "plucker/geometry/so3.h"

namespace plucker {
namespace {

TEST(Median, UpperMedianTakesTheUpperMiddleElement) {
  EXPECT_EQ(UpperMedian({}), 0.0);
  EXPECT_EQ(UpperMedian({7.0}), 7.0);
  EXPECT_EQ(UpperMedian({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(UpperMedian({4.0, 1.0, 3.0, 2.0}), 3.0);  // not 2.5: no averaging
  EXPECT_EQ(UpperMedian({5.0, 5.0, -1.0, 9.0, 0.5, 2.0}), 5.0);
}

TEST(Median, MidpointMedianAveragesTheTwoMiddleValues) {
  EXPECT_EQ(MidpointMedian({}), 0.0);
  EXPECT_EQ(MidpointMedian({7.0}), 7.0);
  EXPECT_EQ(MidpointMedian({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(MidpointMedian({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_EQ(MidpointMedian({5.0, 5.0, -1.0, 9.0, 0.5, 2.0}), 3.5);
}

TEST(Median, BothAgreeForAnOddCount) {
  const std::vector<double> v = {0.3, -2.0, 8.5, 1.25, 4.0, 4.0, -0.5};
  EXPECT_EQ(UpperMedian(v), MidpointMedian(v));
  EXPECT_EQ(UpperMedian(v), 1.25);
}

TEST(So3Hat, IsTheCrossProductMatrix) {
  const Eigen::Vector3d v(0.3, -1.7, 2.2), w(-0.8, 0.4, 1.1);
  const Eigen::Matrix3d S = Hat(v);
  EXPECT_LT((S * w - v.cross(w)).norm(), 1e-15);
  EXPECT_LT((S + S.transpose()).norm(), 1e-15);  // skew-symmetric
  EXPECT_EQ(S(0, 1), -v.z());
  EXPECT_EQ(S(0, 2), v.y());
  EXPECT_EQ(S(1, 2), -v.x());
  EXPECT_EQ((Vee(S) - v).norm(), 0.0);
  EXPECT_EQ(Hat(Eigen::Vector3d::Zero().eval()).norm(), 0.0);
}

}  // namespace
}  // namespace plucker
