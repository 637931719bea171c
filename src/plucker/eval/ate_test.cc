#include "plucker/eval/ate.h"

#include <gtest/gtest.h>

#include "plucker/eval/eval_test_utils.h"
#include "plucker/eval/statistics.h"

namespace plucker {
namespace eval {
namespace {

std::vector<SE3d> Moved(const std::vector<SE3d>& poses, const Similarity& S) {
  std::vector<SE3d> out;
  for (const SE3d& T : poses) out.push_back(S.Apply(T));
  return out;
}

Similarity SomeSimilarity(double scale) {
  Similarity S;
  S.R = Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -1, 0.5).normalized()).matrix();
  S.t = Eigen::Vector3d(5, -3, 12);
  S.scale = scale;
  return S;
}

TEST(Ate, Se3AlignmentOfARotatedCopyGivesZero) {
  const std::vector<SE3d> gt = testing::Curve(300);
  const AteResult r = ComputeAte(gt, Moved(gt, SomeSimilarity(1.0)));
  EXPECT_LT(r.translation_m.rmse, 1e-9);
  EXPECT_LT(r.translation_m.max, 1e-9);
  EXPECT_LT(r.rotation_deg.max, 1e-6);
  ASSERT_EQ(r.aligned_estimate.size(), gt.size());
  EXPECT_LT((r.aligned_estimate[100].translation() - gt[100].translation()).norm(), 1e-9);
  // Without alignment the same copy is far off.
  AteOptions none;
  none.align = AlignmentMode::kNone;
  EXPECT_GT(ComputeAte(gt, Moved(gt, SomeSimilarity(1.0)), none).translation_m.rmse, 1.0);
}

TEST(Ate, Sim3AlignmentRecoversAScaledCopy) {
  const std::vector<SE3d> gt = testing::Curve(300);
  const std::vector<SE3d> est = Moved(gt, SomeSimilarity(0.37));
  AteOptions options;
  options.align = AlignmentMode::kSim3;
  const AteResult r = ComputeAte(gt, est, options);
  EXPECT_LT(r.translation_m.rmse, 1e-9);
  EXPECT_NEAR(r.alignment.scale, 1.0 / 0.37, 1e-9);
  options.align = AlignmentMode::kSE3;
  EXPECT_GT(ComputeAte(gt, est, options).translation_m.rmse, 1.0);
}

TEST(Ate, ConstantOffsetWithoutAlignmentIsTheOffset) {
  const std::vector<SE3d> gt = testing::StraightLine(20, 1.0);
  std::vector<SE3d> est;
  for (const SE3d& T : gt)
    est.emplace_back(T.rotation(), T.translation() + Eigen::Vector3d(0, 3, 4));
  AteOptions options;
  options.align = AlignmentMode::kNone;
  const AteResult r = ComputeAte(gt, est, options);
  EXPECT_NEAR(r.translation_m.rmse, 5.0, 1e-12);
  EXPECT_NEAR(r.translation_m.median, 5.0, 1e-12);
  EXPECT_NEAR(r.distance.back(), 19.0, 1e-12);
}

TEST(Ate, RejectsBadInput) {
  const std::vector<SE3d> gt = testing::StraightLine(5, 1.0);
  EXPECT_THROW(ComputeAte(gt, testing::StraightLine(4, 1.0)), std::invalid_argument);
  EXPECT_THROW(ComputeAte({}, {}), std::invalid_argument);
  AteOptions sim3;
  sim3.align = AlignmentMode::kSim3;
  EXPECT_THROW(ComputeAte(gt, testing::StraightLine(5, 0.0), sim3), std::invalid_argument);
}

TEST(Statistics, HandComputed) {
  const ErrorStatistics s = ComputeStatistics({3.0, 1.0, 4.0, 2.0});
  EXPECT_EQ(s.count, 4);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(30.0 / 4));
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 4.0);
  EXPECT_DOUBLE_EQ(s.std_dev, std::sqrt(1.25));
  EXPECT_DOUBLE_EQ(ComputeStatistics({5.0, 1.0, 3.0}).median, 3.0);
  EXPECT_EQ(ComputeStatistics({}).count, 0);
}

TEST(Statistics, PercentileInterpolates) {
  EXPECT_DOUBLE_EQ(Percentile({3.0, 1.0, 4.0, 2.0}, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(Percentile({3.0, 1.0, 4.0, 2.0}, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(Percentile({3.0, 1.0, 4.0, 2.0}, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(Percentile({0.0, 10.0}, 0.95), 9.5);
  EXPECT_DOUBLE_EQ(Percentile({7.0}, 0.95), 7.0);
  EXPECT_DOUBLE_EQ(Percentile({}, 0.5), 0.0);
}

TEST(RotationAngle, StableAndSignFree) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.25, Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(RotationAngle(q), 0.25, 1e-15);
  Eigen::Quaterniond neg = q;
  neg.coeffs() = -neg.coeffs();
  EXPECT_NEAR(RotationAngle(neg), 0.25, 1e-15);
  EXPECT_NEAR(RotationAngle(Eigen::Quaterniond(Eigen::AngleAxisd(1e-9, Eigen::Vector3d::UnitX()))),
              1e-9, 1e-20);
}

}  // namespace
}  // namespace eval
}  // namespace plucker
