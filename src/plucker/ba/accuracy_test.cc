#include "plucker/ba/accuracy.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace ba {
namespace {

// Ground truth: cameras on a curve, points and segments around them.
struct GroundTruth {
  std::vector<SE3d> T_w_c;
  std::vector<Eigen::Vector3d> points;
  std::vector<WorldSegment> segments;
};

GroundTruth MakeGroundTruth(verify::Rng& rng) {
  GroundTruth gt;
  for (int i = 0; i < 10; ++i) {
    gt.T_w_c.push_back(SE3d(verify::RandomRotation(rng), Eigen::Vector3d(i, 0.1 * i * i, 0.5)));
    gt.points.push_back(verify::RandomVector(rng, 20.0));
    gt.segments.push_back({verify::RandomVector(rng, 20.0), verify::RandomVector(rng, 20.0)});
  }
  return gt;
}

// The ground truth seen in another similarity frame: exact up to the gauge.
BundleAdjustmentData InSimilarityFrame(const GroundTruth& gt, const eval::Similarity& S) {
  BundleAdjustmentData state;
  for (const SE3d& T : gt.T_w_c) state.T_w_c.push_back(S.Apply(T));
  for (const Eigen::Vector3d& p : gt.points) state.points_w.push_back(S * p);
  for (const WorldSegment& s : gt.segments) {
    state.lines_w.push_back(LineFromPoints<double>(S * s.a_w, S * s.b_w));
  }
  return state;
}

TEST(CompareToGroundTruth, Sim3AlignmentRemovesTheGaugeOfPosesPointsAndLines) {
  verify::Rng rng(5);
  const GroundTruth gt = MakeGroundTruth(rng);
  eval::Similarity S;
  S.R = verify::RandomRotation(rng).toRotationMatrix();
  S.t = verify::RandomVector(rng, 5.0);
  S.scale = 1.03;
  const BundleAdjustmentData state = InSimilarityFrame(gt, S);
  const ProblemAccuracy raw =
      CompareToGroundTruth(state, gt.T_w_c, gt.points, gt.segments, eval::AlignmentMode::kNone);
  EXPECT_GT(raw.points_m.median, 0.1);
  EXPECT_GT(raw.lines.distance_m.median, 0.1);
  const ProblemAccuracy aligned =
      CompareToGroundTruth(state, gt.T_w_c, gt.points, gt.segments, eval::AlignmentMode::kSim3);
  EXPECT_NEAR(aligned.scale, 1.0 / 1.03, 1e-12);
  EXPECT_LT(aligned.poses.rotation_deg.max, 1e-9);
  EXPECT_LT(aligned.poses.translation_m.max, 1e-9);
  EXPECT_LT(aligned.points_m.max, 1e-9);
  EXPECT_LT(aligned.lines.distance_m.max, 1e-9);
  EXPECT_LT(aligned.lines.direction_deg.max, 1e-5);  // acos near 1
  EXPECT_EQ(aligned.lines.invalid, 0);
  EXPECT_EQ(aligned.points_m.count, 10);
}

TEST(CompareToGroundTruth, RefusesAnUndefinedAlignment) {
  verify::Rng rng(6);
  const GroundTruth gt = MakeGroundTruth(rng);
  BundleAdjustmentData state = InSimilarityFrame(gt, eval::Similarity());
  state.T_w_c.pop_back();
  EXPECT_THROW(
      CompareToGroundTruth(state, gt.T_w_c, gt.points, gt.segments, eval::AlignmentMode::kSim3),
      std::invalid_argument);
}

}  // namespace
}  // namespace ba
}  // namespace plucker
