#include "plucker/eval/line_coverage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace plucker {
namespace eval {
namespace {

TEST(LineCoverage, PointSegmentDistance) {
  const Segment2d s(0, 0, 10, 0);
  EXPECT_DOUBLE_EQ(PointSegmentDistance({5, 3}, s), 3.0);    // beside the middle
  EXPECT_DOUBLE_EQ(PointSegmentDistance({-3, 4}, s), 5.0);   // beyond the first endpoint
  EXPECT_DOUBLE_EQ(PointSegmentDistance({13, -4}, s), 5.0);  // beyond the second
  EXPECT_DOUBLE_EQ(PointSegmentDistance({4, 3}, Segment2d(1, 1, 1, 1)), std::sqrt(13.0));
}

TEST(LineCoverage, IdenticalSetsArePerfect) {
  const std::vector<Segment2d> gt = {{0, 0, 100, 0}, {10, 10, 10, 60}};
  const LineCoverage c = ComputeLineCoverage(gt, gt, 0.0);
  EXPECT_DOUBLE_EQ(c.detected_length, 150.0);
  EXPECT_DOUBLE_EQ(c.gt_length, 150.0);
  EXPECT_DOUBLE_EQ(c.Precision(), 1.0);
  EXPECT_DOUBLE_EQ(c.Recall(), 1.0);
  EXPECT_DOUBLE_EQ(c.F(), 1.0);
}

TEST(LineCoverage, DetectionCoveringHalfOfTheGroundTruth) {
  // Detection on the first half of a 100 px ground-truth segment, 1 px beside it: all of the
  // detection is within tau = 2 of the ground truth (P = 1); the ground truth is covered on
  // [0, 50 + sqrt(2^2 - 1^2)] (R = 51.732/100 up to the 1 px sampling: pieces centred at
  // 0.5 .. 51.5 are covered, 52 pieces).
  const std::vector<Segment2d> gt = {{0, 0, 100, 0}};
  const std::vector<Segment2d> det = {{0, 1, 50, 1}};
  const LineCoverage c = ComputeLineCoverage(det, gt, 2.0);
  EXPECT_DOUBLE_EQ(c.Precision(), 1.0);
  EXPECT_DOUBLE_EQ(c.Recall(), 0.52);
  EXPECT_NEAR(c.F(), 2 * 0.52 / 1.52, 1e-12);
  // Beyond tau the same detection covers nothing.
  const LineCoverage far = ComputeLineCoverage(det, gt, 0.5);
  EXPECT_DOUBLE_EQ(far.Precision(), 0.0);
  EXPECT_DOUBLE_EQ(far.Recall(), 0.0);
  EXPECT_DOUBLE_EQ(far.F(), 0.0);
}

TEST(LineCoverage, HalfOfADetectionIsOffTheGroundTruth) {
  // A 40 px detection of which 20 px lie on a ground-truth segment and 20 px continue past its
  // end along the same line: points past the end are within tau only for their first tau px.
  const std::vector<Segment2d> gt = {{0, 0, 20, 0}};
  const std::vector<Segment2d> det = {{0, 0, 40, 0}};
  const LineCoverage c = ComputeLineCoverage(det, gt, 3.0);
  EXPECT_DOUBLE_EQ(c.detected_length, 40.0);
  EXPECT_DOUBLE_EQ(c.detected_covered, 23.0);  // pieces centred at 0.5 .. 22.5
  EXPECT_DOUBLE_EQ(c.Precision(), 23.0 / 40.0);
  EXPECT_DOUBLE_EQ(c.Recall(), 1.0);
}

TEST(LineCoverage, PerpendicularSegmentsMeetOnlyNearTheCrossing) {
  const std::vector<Segment2d> gt = {{0, 0, 10, 0}};
  const std::vector<Segment2d> det = {{5, -5, 5, 5}};  // crosses the middle
  const LineCoverage c = ComputeLineCoverage(det, gt, 1.0);
  // Detection pieces centred at y = -4.5 .. 4.5: |y| <= 1 for y = -0.5, 0.5 -> 2 of 10.
  EXPECT_DOUBLE_EQ(c.Precision(), 0.2);
  // Ground-truth pieces centred at x = 0.5 .. 9.5: |x - 5| <= 1 for 4.5, 5.5 -> 2 of 10.
  EXPECT_DOUBLE_EQ(c.Recall(), 0.2);
}

TEST(LineCoverage, EmptySetsAndAccumulation) {
  const std::vector<Segment2d> gt = {{0, 0, 30, 0}}, none;
  const LineCoverage nothing_detected = ComputeLineCoverage(none, gt, 5.0);
  EXPECT_DOUBLE_EQ(nothing_detected.Precision(), 0.0);
  EXPECT_DOUBLE_EQ(nothing_detected.Recall(), 0.0);
  EXPECT_DOUBLE_EQ(nothing_detected.gt_length, 30.0);
  const LineCoverage no_gt = ComputeLineCoverage(gt, none, 5.0);
  EXPECT_DOUBLE_EQ(no_gt.Precision(), 0.0);
  EXPECT_DOUBLE_EQ(no_gt.detected_length, 30.0);
  // Overall figures weigh images by length: a perfect 30 px image plus an empty detection on
  // a 10 px image give R = 30/40, P = 1.
  LineCoverage overall = ComputeLineCoverage(gt, gt, 1.0);
  overall += ComputeLineCoverage(none, {{0, 0, 10, 0}}, 1.0);
  EXPECT_DOUBLE_EQ(overall.Precision(), 1.0);
  EXPECT_DOUBLE_EQ(overall.Recall(), 0.75);
}

TEST(LineCoverage, DegenerateSegmentIsOnePoint) {
  // A zero-length detection has zero length: it neither helps nor hurts precision.
  const LineCoverage c = ComputeLineCoverage({{5, 0, 5, 0}}, {{0, 0, 10, 0}}, 1.0);
  EXPECT_DOUBLE_EQ(c.detected_length, 0.0);
  EXPECT_DOUBLE_EQ(c.Recall(), 0.2);  // the point covers x in [4, 6]: pieces 4.5 and 5.5
}

TEST(LineCoverage, RejectsBadInput) {
  EXPECT_THROW(ComputeLineCoverage({}, {}, -1.0), std::invalid_argument);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(ComputeLineCoverage({{0, 0, nan, 0}}, {}, 1.0), std::invalid_argument);
  EXPECT_THROW(ComputeLineCoverage({}, {{0, 0, 1e300, 0}}, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace eval
}  // namespace plucker
