#include "plucker/sim/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace plucker {
namespace sim {
namespace {

class SceneKindTest : public ::testing::TestWithParam<SceneKind> {};

TEST_P(SceneKindTest, PrimitivesAreConsistent) {
  SceneOptions options;
  options.kind = GetParam();
  const Scene scene = MakeScene(options, 7);
  EXPECT_EQ(scene.kind, GetParam());
  ASSERT_GE(scene.points_w.size(), 600u);
  ASSERT_EQ(scene.point_plane_ids.size(), scene.points_w.size());
  ASSERT_GE(scene.planes_w.size(), 3u);
  ASSERT_GE(scene.segments_w.size(), 30u);
  ASSERT_FALSE(scene.free_space_w.isEmpty());

  for (const Eigen::Vector4d& pi : scene.planes_w) {
    EXPECT_NEAR(pi.head<3>().norm(), 1.0, 1e-12);
    // The normal faces the free space: every corner of the box is on the positive side.
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d corner =
          scene.free_space_w.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c));
      EXPECT_GT(pi.head<3>().dot(corner) + pi(3), 0.0);
    }
  }
  for (std::size_t i = 0; i < scene.points_w.size(); ++i) {
    const int id = scene.point_plane_ids[i];
    ASSERT_GE(id, 0);
    ASSERT_LT(id, static_cast<int>(scene.planes_w.size()));
    const Eigen::Vector4d& pi = scene.planes_w[id];
    EXPECT_NEAR(pi.head<3>().dot(scene.points_w[i]) + pi(3), 0.0, 1e-9);
  }
  // Segments run in all three directions (horizontal along x, along y, vertical).
  int along[3] = {0, 0, 0};
  for (const LineSegment3& s : scene.segments_w) {
    const Eigen::Vector3d d = s.b_w - s.a_w;
    ASSERT_GT(d.norm(), 1e-6);
    ASSERT_TRUE(s.a_w.allFinite() && s.b_w.allFinite());
    int axis;
    d.cwiseAbs().maxCoeff(&axis);
    ++along[axis];
  }
  for (int axis = 0; axis < 3; ++axis) EXPECT_GE(along[axis], 8) << "axis " << axis;
}

TEST_P(SceneKindTest, DeterministicGivenSeed) {
  SceneOptions options;
  options.kind = GetParam();
  const Scene a = MakeScene(options, 3), b = MakeScene(options, 3), c = MakeScene(options, 4);
  ASSERT_EQ(a.points_w.size(), b.points_w.size());
  ASSERT_EQ(a.segments_w.size(), b.segments_w.size());
  for (std::size_t i = 0; i < a.points_w.size(); ++i) EXPECT_EQ(a.points_w[i], b.points_w[i]);
  for (std::size_t i = 0; i < a.segments_w.size(); ++i) {
    EXPECT_EQ(a.segments_w[i].a_w, b.segments_w[i].a_w);
    EXPECT_EQ(a.segments_w[i].b_w, b.segments_w[i].b_w);
  }
  bool differs =
      a.points_w.size() != c.points_w.size() || a.segments_w.size() != c.segments_w.size();
  for (std::size_t i = 0; !differs && i < a.points_w.size(); ++i) {
    differs = a.points_w[i] != c.points_w[i];
  }
  EXPECT_TRUE(differs);
}

INSTANTIATE_TEST_SUITE_P(AllKinds, SceneKindTest,
                         ::testing::Values(SceneKind::kRoom, SceneKind::kCorridor,
                                           SceneKind::kFacades),
                         [](const ::testing::TestParamInfo<SceneKind>& info) {
                           return SceneKindName(info.param);
                         });

TEST(SceneTest, KindNamesRoundTrip) {
  for (SceneKind k : {SceneKind::kRoom, SceneKind::kCorridor, SceneKind::kFacades}) {
    EXPECT_EQ(ParseSceneKind(SceneKindName(k)), k);
  }
  EXPECT_THROW(ParseSceneKind("castle"), std::invalid_argument);
}

TEST(SceneTest, RejectsInvalidOptions) {
  SceneOptions options;
  options.length = -1.0;
  EXPECT_THROW(MakeScene(options, 1), std::invalid_argument);
  options.length = std::nan("");
  EXPECT_THROW(MakeScene(options, 1), std::invalid_argument);
  options = SceneOptions();
  options.num_points = -5;
  EXPECT_THROW(MakeScene(options, 1), std::invalid_argument);
  options = SceneOptions();
  options.frame_depth = INFINITY;
  EXPECT_THROW(MakeScene(options, 1), std::invalid_argument);
}

TEST(SceneTest, TinyRoomStillValid) {
  SceneOptions options;
  options.length = 1.0;
  options.width = 0.5;
  options.height = 0.4;
  options.num_points = 10;
  const Scene scene = MakeScene(options, 1);
  EXPECT_EQ(scene.points_w.size(), 10u);
  EXPECT_FALSE(scene.free_space_w.isEmpty());
  for (const LineSegment3& s : scene.segments_w) EXPECT_GT((s.b_w - s.a_w).norm(), 1e-6);
}

}  // namespace
}  // namespace sim
}  // namespace plucker
