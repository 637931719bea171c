#include "plucker/eval/rpe.h"

#include <gtest/gtest.h>

#include "plucker/eval/eval_test_utils.h"

namespace plucker {
namespace eval {
namespace {

TEST(Rpe, IdenticalTrajectoriesGiveZero) {
  const std::vector<SE3d> gt = testing::Curve(200);
  for (double delta : {1.0, 7.0}) {
    RpeOptions options;
    options.delta = delta;
    const RpeResult r = ComputeRpe(gt, gt, options);
    EXPECT_EQ(static_cast<int>(r.first.size()), 200 - static_cast<int>(delta));
    EXPECT_LT(r.translation_m.max, 1e-12);
    EXPECT_LT(r.rotation_deg.max, 1e-6);
  }
}

TEST(Rpe, ScaleDriftGivesTheHandComputedErrorByFramesAndByMetres) {
  const std::vector<SE3d> gt = testing::StraightLine(50, 1.0);
  const std::vector<SE3d> est = testing::StraightLine(50, 1.1);
  RpeOptions options;
  options.delta = 2;
  RpeResult r = ComputeRpe(gt, est, options);
  EXPECT_EQ(r.first.size(), 48u);
  EXPECT_NEAR(r.translation_m.rmse, 0.2, 1e-12);
  EXPECT_NEAR(r.translation_m.max, 0.2, 1e-12);
  // By distance: 5 m of ground truth = 5 frames here, error 0.5 m.
  options.delta = 5.0;
  options.unit = DeltaUnit::kMeters;
  r = ComputeRpe(gt, est, options);
  EXPECT_EQ(r.first.size(), 45u);
  EXPECT_EQ(r.last[0], 5);
  EXPECT_NEAR(r.translation_m.mean, 0.5, 1e-12);
  // Sim(3) alignment removes a pure scale error.
  options.align = AlignmentMode::kSim3;
  EXPECT_LT(ComputeRpe(gt, est, options).translation_m.max, 1e-12);
}

TEST(Rpe, KnownRotationDrift) {
  const std::vector<SE3d> gt = testing::StraightLine(30, 1.0);
  std::vector<SE3d> est;
  for (int i = 0; i < 30; ++i) {
    est.emplace_back(Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * i, Eigen::Vector3d::UnitY())),
                     gt[i].translation());
  }
  const RpeResult r = ComputeRpe(gt, est);
  EXPECT_NEAR(r.rotation_deg.median, 0.01 * 180.0 / M_PI, 1e-9);
}

TEST(Rpe, RejectsBadInputWithAClearMessage) {
  const std::vector<SE3d> gt = testing::StraightLine(5, 1.0);
  RpeOptions options;
  options.delta = 5;
  EXPECT_THROW(ComputeRpe(gt, gt, options), std::invalid_argument);  // no pair fits
  options.delta = 1.5;
  EXPECT_THROW(ComputeRpe(gt, gt, options), std::invalid_argument);  // fractional frames
  options.delta = 0;
  EXPECT_THROW(ComputeRpe(gt, gt, options), std::invalid_argument);
  options.delta = 100;
  options.unit = DeltaUnit::kMeters;
  try {
    ComputeRpe(gt, gt, options);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("path is"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ComputeRpe(gt, testing::StraightLine(6, 1.0)), std::invalid_argument);
}

}  // namespace
}  // namespace eval
}  // namespace plucker
