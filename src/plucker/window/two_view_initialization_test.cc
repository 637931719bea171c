// The two-view start (two_view_initialization.h) on a simulated room: the rotation check against a
// known relative rotation (e.g. the gyroscope's).
#include "plucker/window/two_view_initialization.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "plucker/sim/camera_observations.h"

namespace plucker {
namespace window {
namespace {

TEST(TwoViewInitialization, AKnownRotationRefusesADisagreeingEssentialMatrix) {
  sim::CameraSimulationOptions o;  // the room, 1 px noise
  o.scene.kind = sim::SceneKind::kRoom;
  o.num_frames = 10;
  o.seed = 4;
  const sim::CameraSimulation s = sim::SimulateCamera(o);
  std::vector<std::vector<sensor::PointObservation>> points(s.frame_times.size());
  for (const auto& p : s.points) points[p.frame].push_back(p);
  const int a = 0, b = 8;
  const SE3d T_w_ca = s.T_w_b_gt[a] * s.rig.T_b_c, T_w_cb = s.T_w_b_gt[b] * s.rig.T_b_c;
  const Eigen::Matrix3d R_b_a = (T_w_cb.Inverse() * T_w_ca).RotationMatrix();
  const TwoViewResult free = InitializeTwoView(s.rig.K, points[a], points[b]);
  ASSERT_TRUE(free.ok) << free.message;
  EXPECT_EQ(free.rotation_disagreement_deg, 0.0);
  const TwoViewResult agree = InitializeTwoView(s.rig.K, points[a], points[b], {}, R_b_a);
  ASSERT_TRUE(agree.ok) << agree.message;
  std::printf("two-view rotation against the truth: %.3f deg (1 px noise, frames %d-%d)\n",
              agree.rotation_disagreement_deg, a, b);
  EXPECT_GT(agree.rotation_disagreement_deg, 0.0);
  EXPECT_LT(agree.rotation_disagreement_deg, TwoViewOptions().max_rotation_disagreement_deg);
  EXPECT_EQ(agree.T_b_a.translation(), free.T_b_a.translation());  // the check changes nothing
  const Eigen::Matrix3d off =
      Eigen::AngleAxisd(6.0 * M_PI / 180.0, Eigen::Vector3d(1, 2, 3).normalized()) * R_b_a;
  const TwoViewResult refused = InitializeTwoView(s.rig.K, points[a], points[b], {}, off);
  EXPECT_FALSE(refused.ok);
  EXPECT_GT(refused.rotation_disagreement_deg, 4.0);
  EXPECT_NE(refused.message.find("disagrees"), std::string::npos) << refused.message;
  TwoViewOptions loose;
  loose.max_rotation_disagreement_deg = 9.0;
  EXPECT_TRUE(InitializeTwoView(s.rig.K, points[a], points[b], loose, off).ok);
}

}  // namespace
}  // namespace window
}  // namespace plucker
