#include "plucker/eval/line_tracks.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "plucker/eval/eval_test_utils.h"
#include "plucker/geometry/point_projection.h"

namespace plucker {
namespace eval {
namespace {

PinholeIntrinsics K() { return testing::KittiLikeCamera(); }

// A car-like sequence: cameras 1 m apart along z, looking along z, with a small sideways drift.
std::vector<SE3d> Poses(int n, double drift = 0.1) {
  std::vector<SE3d> poses;
  for (int i = 0; i < n; ++i)
    poses.emplace_back(Eigen::Quaterniond::Identity(), Eigen::Vector3d(drift * i, 0, 1.0 * i));
  return poses;
}

sensor::SegmentObservation See(const std::vector<SE3d>& poses, int frame, int id,
                               const Eigen::Vector3d& P, const Eigen::Vector3d& Q,
                               const Eigen::Vector2d& offset = Eigen::Vector2d::Zero()) {
  sensor::SegmentObservation o;
  o.frame = frame;
  o.line_id = id;
  o.s_px = *ProjectPoint(K(), poses[frame], P) + offset;
  o.e_px = *ProjectPoint(K(), poses[frame], Q) + offset;
  return o;
}

TEST(LineTracks, CorrectWrongUnconstrainedAndShort) {
  const std::vector<SE3d> poses = Poses(6);
  std::vector<sensor::SegmentObservation> obs;
  // 0: a vertical pole edge, seen 5 times with 0.5 px noise-like offsets: correct.
  const Eigen::Vector3d P0(6, -2, 12), Q0(6, 1, 12);
  for (int f = 0; f < 5; ++f)
    obs.push_back(See(poses, f, 0, P0, Q0, Eigen::Vector2d(0.3 * (f % 2), 0)));
  // 1: the first 3 views of one edge, then 2 of another 1 m away: wrong.
  const Eigen::Vector3d P1(-6, -2, 14), Q1(-6, 1, 14);
  for (int f = 0; f < 5; ++f) {
    const Eigen::Vector3d shift = f < 3 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(1, 0, 0);
    obs.push_back(See(poses, f, 1, P1 + shift, Q1 + shift));
  }
  // 2: a line along the direction of travel through the camera path's plane: unconstrained.
  const Eigen::Vector3d P2(0.1 * 30, 0, 30), Q2(0.1 * 40, 0, 40);  // on the cameras' line
  const Eigen::Vector3d up(0, 1.5, 0);
  for (int f = 0; f < 4; ++f) obs.push_back(See(poses, f, 2, P2 + up, Q2 + up));
  // 3: two views only: short. -1: an outlier, ignored.
  for (int f = 0; f < 2; ++f) obs.push_back(See(poses, f, 3, P0 + up, Q0 + up));
  obs.push_back(See(poses, 0, -1, P1, Q0));
  const LineTrackQuality q = EvaluateLineTracks(K(), poses, obs);
  ASSERT_EQ(q.results.size(), 4u);
  EXPECT_EQ(q.results[0].verdict, TrackVerdict::kCorrect);
  EXPECT_LT(q.results[0].max_error_px, 0.5);
  EXPECT_EQ(q.results[1].verdict, TrackVerdict::kWrong);
  EXPECT_GT(q.results[1].max_error_px, 2.0);
  EXPECT_EQ(q.results[2].verdict, TrackVerdict::kUnconstrained) << q.results[2].reason;
  EXPECT_EQ(q.results[3].verdict, TrackVerdict::kShort);
  EXPECT_EQ(q.tracks, 4);
  EXPECT_EQ(q.evaluated, 3);
  EXPECT_EQ(q.correct, 1);
  EXPECT_EQ(q.wrong, 1);
  EXPECT_EQ(q.unconstrained, 1);
  EXPECT_DOUBLE_EQ(q.precision(), 0.5);
  EXPECT_EQ(q.observations, 16);
  EXPECT_EQ(q.frames, 5);
  EXPECT_EQ(q.length_histogram.at(5), 2);
  EXPECT_EQ(q.length_histogram.at(4), 1);
  EXPECT_EQ(q.length_histogram.at(2), 1);
  EXPECT_DOUBLE_EQ(q.median_length, 5.0);
  EXPECT_NEAR(q.mean_length, 14.0 / 3.0, 1e-12);
  EXPECT_NEAR(q.segments_per_frame, 14.0 / 5.0, 1e-12);
  // A looser threshold makes the wrong track correct.
  LineTrackQualityOptions loose;
  loose.max_error_px = 1000;
  EXPECT_EQ(EvaluateLineTracks(K(), poses, obs, loose).correct, 2);
}

TEST(LineTracks, EmptyAndBadInput) {
  const std::vector<SE3d> poses = Poses(3);
  const LineTrackQuality none = EvaluateLineTracks(K(), poses, {});
  EXPECT_EQ(none.tracks, 0);
  EXPECT_EQ(none.precision(), 0.0);
  std::vector<sensor::SegmentObservation> obs = {
      See(poses, 0, 0, Eigen::Vector3d(1, 0, 10), Eigen::Vector3d(1, 1, 10))};
  obs[0].frame = 3;
  EXPECT_THROW(EvaluateLineTracks(K(), poses, obs), std::invalid_argument);
  obs[0].frame = 0;
  obs.push_back(obs[0]);  // the same track twice in one frame
  EXPECT_THROW(EvaluateLineTracks(K(), poses, obs), std::invalid_argument);
  PinholeIntrinsics bad = K();
  bad.fx = 0;
  EXPECT_THROW(EvaluateLineTracks(bad, poses, {}), std::invalid_argument);
  LineTrackQualityOptions o;
  o.min_views = 1;
  EXPECT_THROW(EvaluateLineTracks(K(), poses, {}, o), std::invalid_argument);
}

}  // namespace
}  // namespace eval
}  // namespace plucker
