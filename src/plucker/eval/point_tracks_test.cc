#include "plucker/eval/point_tracks.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "plucker/eval/eval_test_utils.h"
#include "plucker/geometry/point_projection.h"

namespace plucker {
namespace eval {
namespace {

PinholeIntrinsics K() { return testing::KittiLikeCamera(); }

// Cameras 1 m apart sideways, looking along z.
std::vector<SE3d> Poses(int n) {
  std::vector<SE3d> poses;
  for (int i = 0; i < n; ++i)
    poses.emplace_back(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1.0 * i, 0, 0));
  return poses;
}

sensor::PointObservation See(const std::vector<SE3d>& poses, int frame, int id,
                             const Eigen::Vector3d& p_w,
                             const Eigen::Vector2d& offset = Eigen::Vector2d::Zero()) {
  return {frame, id, *ProjectPoint(K(), poses[frame], p_w) + offset};
}

TEST(PointTracks, CorrectWrongShortAndIgnored) {
  const std::vector<SE3d> poses = Poses(5);
  std::vector<sensor::PointObservation> obs;
  const Eigen::Vector3d a(1, 0.5, 10), b(-2, 1, 12), c(3, -1, 8);
  // 0: seen 5 times with 0.3 px offsets: correct, its worst error under 1 px.
  for (int f = 0; f < 5; ++f) obs.push_back(See(poses, f, 0, a, Eigen::Vector2d(0.3 * (f % 2), 0)));
  // 1: 3 views of one point, then 2 of another 1 m away: wrong.
  for (int f = 0; f < 5; ++f)
    obs.push_back(See(poses, f, 1, f < 3 ? b : b + Eigen::Vector3d::UnitX()));
  // 2: one view only: counted, not evaluated. -1: ignored.
  obs.push_back(See(poses, 0, 2, c));
  obs.push_back(See(poses, 1, -1, c));
  const PointTrackQuality q = EvaluatePointTracks(K(), poses, obs);
  EXPECT_EQ(q.tracks, 3);
  EXPECT_EQ(q.evaluated, 2);
  EXPECT_EQ(q.correct, 1);
  EXPECT_EQ(q.wrong, 1);
  EXPECT_EQ(q.failed, 0);
  EXPECT_DOUBLE_EQ(q.precision(), 0.5);
  ASSERT_EQ(q.results.size(), 3u);
  EXPECT_TRUE(q.results[0].judged);
  EXPECT_GT(q.results[0].max_error_px, 0.0);
  EXPECT_LT(q.results[0].max_error_px, 1.0);
  EXPECT_GT(q.results[1].max_error_px, 10.0);  // 1 m at 12 m is ~58 px between the halves
  EXPECT_FALSE(q.results[2].judged);
  EXPECT_EQ(q.results[2].views, 1);
}

TEST(PointTracks, RaysThatMeetBehindTheCamerasFail) {
  const std::vector<SE3d> poses = Poses(2);
  // The same pixel in both views: parallel rays, no point in front of the cameras.
  const std::vector<sensor::PointObservation> obs = {{0, 7, {600, 180}}, {1, 7, {600, 180}}};
  const PointTrackQuality q = EvaluatePointTracks(K(), poses, obs);
  EXPECT_EQ(q.evaluated, 1);
  EXPECT_EQ(q.failed, 1);
  EXPECT_EQ(q.correct + q.wrong, 0);
  EXPECT_DOUBLE_EQ(q.precision(), 0.0);
}

TEST(PointTracks, BadInputIsRefused) {
  const std::vector<SE3d> poses = Poses(2);
  EXPECT_THROW(EvaluatePointTracks(K(), poses, {{2, 0, {1, 1}}}), std::invalid_argument);
  EXPECT_THROW(EvaluatePointTracks(K(), poses, {{-1, 0, {1, 1}}}), std::invalid_argument);
  PinholeIntrinsics bad = K();
  bad.fx = -1;
  EXPECT_THROW(EvaluatePointTracks(bad, poses, {}), std::invalid_argument);
  PointTrackQualityOptions o;
  o.min_views = 1;
  EXPECT_THROW(EvaluatePointTracks(K(), poses, {}, o), std::invalid_argument);
}

}  // namespace
}  // namespace eval
}  // namespace plucker
