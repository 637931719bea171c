#include "plucker/sim/camera_observations.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "plucker/geometry/plucker_line.h"

namespace plucker {
namespace sim {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

CameraSimulationOptions Options(SceneKind kind, std::uint64_t seed) {
  CameraSimulationOptions o;
  o.scene.kind = kind;
  o.num_frames = 40;
  o.seed = seed;
  o.simulate_imu = false;
  return o;
}

// Pixel image line of the 3D line through a_w, b_w: l = K_line n_c (docs/conventions.md).
Eigen::Vector3d ImageLine(const Vector3d& a_w, const Vector3d& b_w, const SE3d& T_w_c,
                          const PinholeIntrinsics& K) {
  const SE3d T_c_w = T_w_c.Inverse();
  const Vector3d n_c = (T_c_w * a_w).cross(T_c_w * b_w);
  Eigen::Matrix3d K_line;
  K_line << K.fy, 0, 0, 0, K.fx, 0, -K.fy * K.cx, -K.fx * K.cy, K.fx * K.fy;
  return K_line * n_c;
}

double PixelDistanceToLine(const Vector2d& uv, const Eigen::Vector3d& l) {
  return (l(0) * uv.x() + l(1) * uv.y() + l(2)) / l.head<2>().norm();
}

bool InsideImage(const Vector2d& uv, const sensor::CameraRig& rig, double tol) {
  return uv.x() >= -tol && uv.x() <= rig.width - 1 + tol && uv.y() >= -tol &&
         uv.y() <= rig.height - 1 + tol;
}

class CameraKindTest : public ::testing::TestWithParam<SceneKind> {};

TEST_P(CameraKindTest, NoiseFreeObservationsReprojectExactly) {
  CameraSimulationOptions o = Options(GetParam(), 3);
  o.obs.pixel_sigma = 0.0;
  const CameraSimulation sim = SimulateCamera(o);
  ASSERT_EQ(sim.T_w_c_gt.size(), 40u);
  std::vector<int> points_per_frame(40, 0), segments_per_frame(40, 0);
  for (std::size_t i = 0; i < sim.T_w_c_gt.size(); ++i) {
    const SE3d expected = sim.T_w_b_gt[i] * sim.rig.T_b_c;
    EXPECT_LT((sim.T_w_c_gt[i].Matrix() - expected.Matrix()).norm(), 1e-12);
  }
  for (const sensor::PointObservation& obs : sim.points) {
    ASSERT_GE(obs.point_id, 0);
    const SE3d& T_w_c = sim.T_w_c_gt[obs.frame];
    const Vector3d p_c = T_w_c.Inverse() * sim.scene.points_w[obs.point_id];
    ASSERT_GT(p_c.z(), o.obs.min_depth);
    const Vector2d uv = sim.rig.K.ToPixel<double>(p_c.hnormalized());
    EXPECT_LT((uv - obs.uv).norm(), 1e-9);
    EXPECT_TRUE(InsideImage(obs.uv, sim.rig, 0.0));
    ++points_per_frame[obs.frame];
  }
  for (const sensor::SegmentObservation& obs : sim.segments) {
    ASSERT_GE(obs.line_id, 0);
    const LineSegment3& seg = sim.scene.segments_w[obs.line_id];
    const Eigen::Vector3d l = ImageLine(seg.a_w, seg.b_w, sim.T_w_c_gt[obs.frame], sim.rig.K);
    EXPECT_LT(std::abs(PixelDistanceToLine(obs.s_px, l)), 1e-6);
    EXPECT_LT(std::abs(PixelDistanceToLine(obs.e_px, l)), 1e-6);
    EXPECT_TRUE(InsideImage(obs.s_px, sim.rig, 1e-6));
    EXPECT_TRUE(InsideImage(obs.e_px, sim.rig, 1e-6));
    EXPECT_GE((obs.e_px - obs.s_px).norm(), o.obs.min_segment_px);
    ++segments_per_frame[obs.frame];
  }
  // The camera looks at the scene: every frame sees plenty of points and segments.
  EXPECT_GE(*std::min_element(points_per_frame.begin(), points_per_frame.end()), 15);
  EXPECT_GE(*std::min_element(segments_per_frame.begin(), segments_per_frame.end()), 10);
  RecordProperty("min_points_per_frame",
                 *std::min_element(points_per_frame.begin(), points_per_frame.end()));
  RecordProperty("min_segments_per_frame",
                 *std::min_element(segments_per_frame.begin(), segments_per_frame.end()));
}

TEST_P(CameraKindTest, DeterministicGivenSeed) {
  const CameraSimulation a = SimulateCamera(Options(GetParam(), 5));
  const CameraSimulation b = SimulateCamera(Options(GetParam(), 5));
  const CameraSimulation c = SimulateCamera(Options(GetParam(), 6));
  ASSERT_EQ(a.points.size(), b.points.size());
  ASSERT_EQ(a.segments.size(), b.segments.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].point_id, b.points[i].point_id);
    EXPECT_EQ(a.points[i].uv, b.points[i].uv);
  }
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    EXPECT_EQ(a.segments[i].line_id, b.segments[i].line_id);
    EXPECT_EQ(a.segments[i].s_px, b.segments[i].s_px);
    EXPECT_EQ(a.segments[i].e_px, b.segments[i].e_px);
  }
  for (std::size_t i = 0; i < a.T_w_c_gt.size(); ++i) {
    EXPECT_EQ(a.T_w_c_gt[i].translation(), b.T_w_c_gt[i].translation());
  }
  EXPECT_NE(a.T_w_c_gt[1].translation(), c.T_w_c_gt[1].translation());
  EXPECT_TRUE(a.points.size() != c.points.size() || a.points[0].uv != c.points[0].uv);
}

INSTANTIATE_TEST_SUITE_P(AllKinds, CameraKindTest,
                         ::testing::Values(SceneKind::kRoom, SceneKind::kCorridor,
                                           SceneKind::kFacades),
                         [](const ::testing::TestParamInfo<SceneKind>& info) {
                           return SceneKindName(info.param);
                         });

sensor::CameraRig TestRig() { return DefaultRig(); }

TEST(ClipSegmentTest, FullyVisibleSegmentIsUnchanged) {
  const sensor::CameraRig rig = TestRig();
  const SE3d T_w_c;  // camera at the origin looking along +z
  const LineSegment3 seg{Vector3d(-0.5, 0.2, 4.0), Vector3d(0.3, -0.1, 5.0)};
  const auto c = ClipSegmentToImage(seg, T_w_c, rig, 0.1, 40.0);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->s0, 0.0);
  EXPECT_EQ(c->s1, 1.0);
  EXPECT_LT((c->s_px - *ProjectVisiblePoint(seg.a_w, T_w_c, rig, 0.1, 40.0)).norm(), 1e-12);
  EXPECT_LT((c->e_px - *ProjectVisiblePoint(seg.b_w, T_w_c, rig, 0.1, 40.0)).norm(), 1e-12);
}

TEST(ClipSegmentTest, SegmentBehindOrBesideCameraIsRejected) {
  const sensor::CameraRig rig = TestRig();
  const SE3d T_w_c;
  EXPECT_FALSE(ClipSegmentToImage({Vector3d(0, 0, -1), Vector3d(1, 0, -3)}, T_w_c, rig, 0.1, 40));
  EXPECT_FALSE(ClipSegmentToImage({Vector3d(50, 0, 1), Vector3d(60, 1, 2)}, T_w_c, rig, 0.1, 40));
  EXPECT_FALSE(ClipSegmentToImage({Vector3d(0, 0, 50), Vector3d(1, 0, 60)}, T_w_c, rig, 0.1, 40));
  EXPECT_FALSE(ClipSegmentToImage({Vector3d(0, 0, 5), Vector3d(0, 0, 5)}, T_w_c, rig, 0.1, 40));
  EXPECT_FALSE(ClipSegmentToImage({Vector3d(0, 0, 5), Vector3d(NAN, 0, 5)}, T_w_c, rig, 0.1, 40));
}

TEST(ClipSegmentTest, SegmentThroughNearPlaneIsClippedIn3D) {
  const sensor::CameraRig rig = TestRig();
  const SE3d T_w_c;
  // From behind the camera to far in front, off-axis: the 2D projection of the behind point
  // would land on the wrong side; clipping in 3D keeps the visible part only.
  const LineSegment3 seg{Vector3d(0.3, 0.2, -2.0), Vector3d(0.5, 0.4, 8.0)};
  const auto c = ClipSegmentToImage(seg, T_w_c, rig, 0.1, 40.0);
  ASSERT_TRUE(c.has_value());
  EXPECT_GT(c->s0, 0.0);
  EXPECT_EQ(c->s1, 1.0);
  EXPECT_TRUE(InsideImage(c->s_px, rig, 1e-9));
  // The clipped start is on the image border (the segment leaves the frustum sideways before
  // reaching the near plane) or on the near plane.
  const bool on_border = std::min({c->s_px.x(), c->s_px.y(), rig.width - 1 - c->s_px.x(),
                                   rig.height - 1 - c->s_px.y()}) < 1e-6;
  EXPECT_TRUE(on_border || std::abs(c->a_c.z() - 0.1) < 1e-12);
}

// Random segments around a random camera: the clipped endpoints are inside the image, on the
// projected line, and the clip is tight (just outside [s0, s1] is invisible).
TEST(ClipSegmentTest, RandomSegmentsClipTightlyOntoTheProjectedLine) {
  const sensor::CameraRig rig = TestRig();
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int clipped_count = 0, partial = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const SE3d T_w_c(ExpSO3<double>(Vector3d(u(rng), u(rng), u(rng))),
                     Vector3d(u(rng), u(rng), u(rng)));
    const Vector3d a = T_w_c * Vector3d(8 * u(rng), 8 * u(rng), 6 + 8 * u(rng));
    const Vector3d b = T_w_c * Vector3d(8 * u(rng), 8 * u(rng), 6 + 8 * u(rng));
    const double near = 0.1, far = 12.0;
    const auto c = ClipSegmentToImage({a, b}, T_w_c, rig, near, far);
    if (!c) continue;
    ++clipped_count;
    ASSERT_LT(c->s0, c->s1);
    EXPECT_TRUE(InsideImage(c->s_px, rig, 1e-6));
    EXPECT_TRUE(InsideImage(c->e_px, rig, 1e-6));
    EXPECT_GE(c->a_c.z(), near - 1e-9);
    EXPECT_LE(c->b_c.z(), far + 1e-9);
    const Eigen::Vector3d l = ImageLine(a, b, T_w_c, rig.K);
    EXPECT_LT(std::abs(PixelDistanceToLine(c->s_px, l)), 1e-6);
    EXPECT_LT(std::abs(PixelDistanceToLine(c->e_px, l)), 1e-6);
    const double step = 1e-6 * std::max(1.0, 1.0 / (b - a).norm());
    if (c->s0 > 0.0) {
      ++partial;
      EXPECT_FALSE(ProjectVisiblePoint(a + (c->s0 - step) * (b - a), T_w_c, rig, near, far));
    }
    if (c->s1 < 1.0) {
      EXPECT_FALSE(ProjectVisiblePoint(a + (c->s1 + step) * (b - a), T_w_c, rig, near, far));
    }
    EXPECT_TRUE(ProjectVisiblePoint(a + 0.5 * (c->s0 + c->s1) * (b - a), T_w_c, rig, near, far));
  }
  EXPECT_GT(clipped_count, 300);
  EXPECT_GT(partial, 100);
}

TEST(CameraObservationTest, OutlierRatioHonoured) {
  for (double ratio : {0.1, 0.3}) {
    CameraSimulationOptions o = Options(SceneKind::kRoom, 8);
    o.obs.outlier_ratio = ratio;
    const CameraSimulation sim = SimulateCamera(o);
    int point_out = 0, seg_out = 0;
    for (const sensor::PointObservation& p : sim.points) {
      point_out += p.point_id == -1;
      EXPECT_TRUE(InsideImage(p.uv, sim.rig, 0.0) || p.point_id >= 0);
    }
    for (const sensor::SegmentObservation& s : sim.segments) {
      if (s.line_id != -1) continue;
      ++seg_out;
      EXPECT_TRUE(InsideImage(s.s_px, sim.rig, 0.0) && InsideImage(s.e_px, sim.rig, 0.0));
      EXPECT_GE((s.e_px - s.s_px).norm(), o.obs.min_segment_px);
    }
    EXPECT_EQ(point_out, sim.stats.num_point_outliers);
    EXPECT_EQ(seg_out, sim.stats.num_segment_outliers);
    EXPECT_NEAR(static_cast<double>(point_out) / sim.points.size(), ratio, 0.005);
    EXPECT_NEAR(static_cast<double>(seg_out) / sim.segments.size(), ratio, 0.005);
  }
}

TEST(CameraObservationTest, PixelNoiseHasConfiguredSigma) {
  CameraSimulationOptions o = Options(SceneKind::kRoom, 4);
  o.obs.pixel_sigma = 1.5;
  const CameraSimulation noisy = SimulateCamera(o);
  double sq = 0;
  long n = 0;
  for (const sensor::PointObservation& obs : noisy.points) {
    const Vector3d p_c = noisy.T_w_c_gt[obs.frame].Inverse() * noisy.scene.points_w[obs.point_id];
    sq += (noisy.rig.K.ToPixel<double>(p_c.hnormalized()) - obs.uv).squaredNorm();
    n += 2;
  }
  ASSERT_GT(n, 2000);
  EXPECT_NEAR(std::sqrt(sq / n), 1.5, 0.05);
}

TEST(CameraObservationTest, ObservationsSortedByFrame) {
  const CameraSimulation sim = SimulateCamera(Options(SceneKind::kCorridor, 2));
  for (std::size_t i = 1; i < sim.points.size(); ++i) {
    EXPECT_LE(sim.points[i - 1].frame, sim.points[i].frame);
  }
  for (std::size_t i = 1; i < sim.segments.size(); ++i) {
    EXPECT_LE(sim.segments[i - 1].frame, sim.segments[i].frame);
  }
}

TEST(CameraObservationTest, CanonicalPoseIsAFixedPoint) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int i = 0; i < 1000; ++i) {
    const SE3d T = CanonicalPose(
        SE3d(ExpSO3<double>(Vector3d(u(rng), u(rng), u(rng))), Vector3d(u(rng), u(rng), u(rng))));
    double p[7];
    T.ToParameters(p);
    const SE3d back = SE3d::FromParameters(p);
    EXPECT_EQ(back.rotation().coeffs(), T.rotation().coeffs());
  }
}

TEST(CameraObservationTest, RejectsInvalidOptions) {
  CameraSimulationOptions o = Options(SceneKind::kRoom, 1);
  o.obs.outlier_ratio = 0.95;
  EXPECT_THROW(SimulateCamera(o), std::invalid_argument);
  o = Options(SceneKind::kRoom, 1);
  o.obs.max_depth = 0.05;
  EXPECT_THROW(SimulateCamera(o), std::invalid_argument);
  o = Options(SceneKind::kRoom, 1);
  o.num_frames = 0;
  EXPECT_THROW(SimulateCamera(o), std::invalid_argument);
  o = Options(SceneKind::kRoom, 1);
  o.rig.K.fx = -1;
  EXPECT_THROW(SimulateCamera(o), std::invalid_argument);
  o = Options(SceneKind::kRoom, 1);
  o.frame_rate_hz = std::nan("");
  EXPECT_THROW(SimulateCamera(o), std::invalid_argument);
}

TEST(CameraObservationTest, ImuCoversTheFrames) {
  CameraSimulationOptions o = Options(SceneKind::kRoom, 1);
  o.simulate_imu = true;
  const CameraSimulation sim = SimulateCamera(o);
  ASSERT_FALSE(sim.imu.empty());
  EXPECT_EQ(sim.imu.front().t, 0.0);
  EXPECT_GE(sim.imu.back().t, sim.frame_times.back() - 1e-12);
  EXPECT_EQ(sim.v_w_gt.size(), sim.frame_times.size());
}

// The recorded sequence (what io writes) carries every measurement, the noise models and the
// ground truth of the simulation unchanged.
TEST(CameraSimulationTest, ToCameraImuSequenceKeepsEverything) {
  CameraSimulationOptions o = Options(SceneKind::kCorridor, 9);
  o.num_frames = 8;
  o.simulate_imu = true;
  o.imu.model.gyro_noise_density = 3e-4;
  o.imu.initial_accel_bias = Vector3d(0.1, -0.2, 0.05);
  o.obs.outlier_ratio = 0.2;
  const CameraSimulation sim = SimulateCamera(o);
  const sensor::CameraImuSequence seq = ToCameraImuSequence(sim);
  ASSERT_TRUE(seq.ground_truth.has_value());
  const sensor::CameraImuGroundTruth& gt = *seq.ground_truth;
  EXPECT_EQ(seq.imu_model.gyro_noise_density, 3e-4);
  EXPECT_EQ(seq.imu_model.rate_hz, o.imu.model.rate_hz);
  EXPECT_EQ(seq.observation_model.outlier_ratio, 0.2);
  EXPECT_EQ(seq.gravity_w, o.imu.gravity_w);
  EXPECT_EQ(gt.initial_accel_bias, o.imu.initial_accel_bias);
  EXPECT_EQ(seq.frame_times, sim.frame_times);
  ASSERT_EQ(gt.T_w_c.size(), 8u);
  ASSERT_EQ(gt.T_w_b.size(), 8u);
  ASSERT_EQ(gt.v_w.size(), 8u);
  for (std::size_t i = 0; i < gt.T_w_c.size(); ++i) {
    EXPECT_EQ(gt.T_w_c[i].Matrix(), sim.T_w_c_gt[i].Matrix());
    EXPECT_EQ(gt.T_w_b[i].Matrix(), sim.T_w_b_gt[i].Matrix());
    EXPECT_EQ(gt.v_w[i], sim.v_w_gt[i]);
  }
  ASSERT_FALSE(sim.imu.empty());
  ASSERT_EQ(seq.imu.size(), sim.imu.size());
  EXPECT_EQ(seq.imu.back().accel, sim.imu.back().accel);
  ASSERT_FALSE(sim.points.empty());
  ASSERT_EQ(seq.points.size(), sim.points.size());
  ASSERT_EQ(seq.segments.size(), sim.segments.size());
  EXPECT_EQ(seq.points.back().uv, sim.points.back().uv);
  EXPECT_EQ(seq.segments.back().e_px, sim.segments.back().e_px);
  EXPECT_EQ(gt.scene_kind, "corridor");
  EXPECT_EQ(gt.points_w, sim.scene.points_w);
  EXPECT_EQ(gt.point_plane_ids, sim.scene.point_plane_ids);
  EXPECT_EQ(gt.planes_w, sim.scene.planes_w);
  ASSERT_EQ(gt.segments_w.size(), sim.scene.segments_w.size());
  EXPECT_EQ(gt.segments_w.back().b_w, sim.scene.segments_w.back().b_w);
  EXPECT_EQ(gt.free_space_w.min(), sim.scene.free_space_w.min());
}

}  // namespace
}  // namespace sim
}  // namespace plucker
