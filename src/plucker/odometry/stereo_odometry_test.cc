// Stereo mode of MonocularOdometry (window.T_c0_c1): the start from one frame's left-right pairs,
// metric scale without an IMU (ATE after SE(3), no scale), and the refusal without a second
// camera's observations.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "plucker/eval/ate.h"
#include "plucker/odometry/monocular_odometry.h"
#include "plucker/sim/camera_observations.h"

namespace plucker {
namespace odometry {
namespace {

using window::FrameInput;

sim::CameraSimulation SimulateStereo(sim::SceneKind scene, int frames) {
  sim::CameraSimulationOptions options;
  options.scene.kind = scene;
  options.num_frames = frames;
  options.seed = 1;
  options.simulate_imu = false;
  options.T_c0_c1 = sim::StereoPose(0.11);
  return sim::SimulateCamera(options);
}

std::vector<FrameInput> Inputs(const sim::CameraSimulation& s, bool right) {
  std::vector<FrameInput> in(s.frame_times.size());
  for (std::size_t i = 0; i < in.size(); ++i) in[i].time = s.frame_times[i];
  for (const auto& p : s.points)
    if (p.point_id >= 0) in[p.frame].points.push_back(p);
  for (const auto& l : s.segments) in[l.frame].segments.push_back(l);
  if (!right) return in;
  for (const auto& p : s.cam1->points)
    if (p.point_id >= 0) in[p.frame].right_points.push_back(p);
  for (const auto& l : s.cam1->segments) in[l.frame].right_segments.push_back(l);
  return in;
}

MonocularOdometryOptions StereoOptions(const sim::CameraSimulation& s) {
  MonocularOdometryOptions o;
  o.window.T_c0_c1 = s.cam1->T_c0_c1;
  return o;
}

double AteSe3(const sim::CameraSimulation& s, const MonocularOdometry& vo) {
  std::vector<SE3d> est;
  for (const auto& r : vo.Trajectory()) est.push_back(r.T_w_c);
  eval::AteOptions ate;
  ate.align = eval::AlignmentMode::kSE3;
  return eval::ComputeAte(s.T_w_c_gt, est, ate).translation_m.rmse;
}

double PathLength(const std::vector<SE3d>& T) {
  double l = 0.0;
  for (std::size_t i = 1; i < T.size(); ++i)
    l += (T[i].translation() - T[i - 1].translation()).norm();
  return l;
}

TEST(StereoOdometry, StartsAtTheFirstFrameWithMetricScale) {
  const sim::CameraSimulation s = SimulateStereo(sim::SceneKind::kRoom, 30);
  const std::vector<FrameInput> in = Inputs(s, true);
  MonocularOdometry vo(s.rig.K, StereoOptions(s));
  const MonocularFrameResult first = vo.AddFrame(in[0]);
  EXPECT_EQ(first.status, MonocularStatus::kInitialized);  // no frame buffered: online at once
  EXPECT_TRUE(first.has_pose);
  for (std::size_t i = 1; i < in.size(); ++i) {
    const MonocularFrameResult r = vo.AddFrame(in[i]);
    EXPECT_TRUE(r.has_pose) << "frame " << i;
  }
  vo.Finish();
  ASSERT_EQ(vo.Maps().size(), 1u);
  EXPECT_EQ(vo.Maps()[0].first, 0);
  EXPECT_EQ(vo.Summary().lost_frames, 0);
  std::vector<SE3d> est;
  for (const auto& r : vo.Trajectory()) est.push_back(r.T_w_c);
  // The scale is the baseline's: the path within 3 % of the truth's, and the ATE after SE(3)
  // (no scale correction) a few centimetres on a path of metres.
  const double ratio = PathLength(est) / PathLength(s.T_w_c_gt);
  EXPECT_NEAR(ratio, 1.0, 0.03);
  EXPECT_LT(AteSe3(s, vo), 0.05);
  EXPECT_GT(PathLength(s.T_w_c_gt), 2.0);
}

TEST(StereoOdometry, LandmarksOfTheStartAreMetric) {
  const sim::CameraSimulation s = SimulateStereo(sim::SceneKind::kRoom, 1);
  const std::vector<FrameInput> in = Inputs(s, true);
  window::SlidingWindowOptions options;
  options.T_c0_c1 = s.cam1->T_c0_c1;
  window::SlidingWindowEstimator window(s.rig.K, options);
  const window::InitializationResult init = window.InitializeStereo(in[0], s.T_w_c_gt[0]);
  ASSERT_TRUE(init.ok);
  EXPECT_GT(init.points, 50);
  std::vector<double> errors;
  for (const auto& [id, p] : window.Points()) errors.push_back((p - s.scene.points_w[id]).norm());
  ASSERT_FALSE(errors.empty());
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  // 1 px noise at fx 400 and b = 0.11 m: depth sigma z^2 / (f b) sqrt(2), 0.3 m at 3 m.
  EXPECT_LT(errors[errors.size() / 2], 0.3);
}

TEST(StereoOdometry, NoSecondCameraObservationsNoStart) {
  const sim::CameraSimulation s = SimulateStereo(sim::SceneKind::kRoom, 5);
  const std::vector<FrameInput> in = Inputs(s, false);
  MonocularOdometry vo(s.rig.K, StereoOptions(s));
  for (const FrameInput& f : in) EXPECT_FALSE(vo.AddFrame(f).has_pose);
  vo.Finish();
  EXPECT_TRUE(vo.Maps().empty());
  EXPECT_NE(vo.StartFailure().find("left-right"), std::string::npos) << vo.StartFailure();
}

TEST(StereoOdometry, InitializeStereoOutsideTheStereoModeThrows) {
  window::SlidingWindowEstimator window(PinholeIntrinsics{400, 400, 320, 240}, {});
  EXPECT_THROW(window.InitializeStereo(FrameInput{}, SE3d()), std::logic_error);
  window::SlidingWindowOptions vi;
  vi.T_c0_c1 = sim::StereoPose(0.11);
  vi.inertial.emplace();
  EXPECT_THROW(window::SlidingWindowEstimator(PinholeIntrinsics{400, 400, 320, 240}, vi),
               std::invalid_argument);
}

}  // namespace
}  // namespace odometry
}  // namespace plucker
