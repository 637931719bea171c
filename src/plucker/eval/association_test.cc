#include "plucker/eval/association.h"

#include <gtest/gtest.h>

#include "plucker/eval/eval_test_utils.h"

namespace plucker {
namespace eval {
namespace {

TEST(Association, ByIndexNeedsEqualCounts) {
  const std::vector<SE3d> a = testing::StraightLine(10, 1.0);
  const AssociatedTrajectories p = AssociateByIndex(a, a);
  EXPECT_EQ(p.gt.size(), 10u);
  EXPECT_FALSE(p.by_time);
  try {
    AssociateByIndex(a, testing::StraightLine(9, 1.0));
    ADD_FAILURE() << "a length mismatch must be an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("10 poses"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("9"), std::string::npos) << e.what();
  }
}

TEST(Association, ByTimePairsNearestWithinToleranceOneToOne) {
  const std::vector<SE3d> gt = testing::StraightLine(5, 1.0);
  const std::vector<double> t_gt = {0.0, 0.1, 0.2, 0.3, 0.4};
  const std::vector<SE3d> est = testing::StraightLine(5, 2.0);
  // 0.005 -> gt 0; 0.095 and 0.11 both nearest gt 1 (0.095 closer wins); 0.25 is 0.05 away from
  // everything (unpaired at 0.02); 0.41 -> gt 4.
  const std::vector<double> t_est = {0.005, 0.095, 0.11, 0.25, 0.41};
  const AssociatedTrajectories p = AssociateByTime(t_gt, gt, t_est, est);
  EXPECT_TRUE(p.by_time);
  EXPECT_EQ(p.index_gt, (std::vector<int>{0, 1, 4}));
  EXPECT_EQ(p.index_est, (std::vector<int>{0, 1, 4}));
  EXPECT_NEAR(p.max_time_difference_used, 0.01, 1e-12);
  EXPECT_EQ(p.count_est, 5);
  EXPECT_EQ(p.times, (std::vector<double>{0.0, 0.1, 0.4}));
}

TEST(Association, ByTimeWithNoOverlapIsAnError) {
  const std::vector<SE3d> gt = testing::StraightLine(3, 1.0);
  EXPECT_THROW(AssociateByTime({0, 1, 2}, gt, {10, 11, 12}, gt), std::invalid_argument);
  EXPECT_THROW(AssociateByTime({0, 1}, gt, {0, 1, 2}, gt), std::invalid_argument);
  EXPECT_THROW(AssociateByTime({2, 1, 0}, gt, {0, 1, 2}, gt), std::invalid_argument);
}

}  // namespace
}  // namespace eval
}  // namespace plucker
