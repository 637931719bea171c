// The two-view start (two_view_initialization.h) on a simulated room: the rotation check against a
// known relative rotation (e.g. the gyroscope's).
#include "plucker/window/two_view_initialization.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <random>

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

// Two views of random points at depths [near, far] in front of camera a (752 x 480, f 458, as
// EuRoC), camera b = (R_b_a, t_b_a), pixel noise sigma.
struct TwoViews {
  PinholeIntrinsics K{458.0, 458.0, 376.0, 240.0};
  std::vector<sensor::PointObservation> a, b;
};
TwoViews MakeTwoViews(const Eigen::Matrix3d& R_b_a, const Eigen::Vector3d& t_b_a, double near,
                      double far, double sigma, unsigned seed) {
  TwoViews v;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), depth(near, far);
  std::normal_distribution<double> noise(0.0, sigma);
  for (int id = 0; v.a.size() < 150 && id < 10000; ++id) {
    const double z = depth(rng);
    const Eigen::Vector3d p_a(u(rng) * 0.7 * z, u(rng) * 0.45 * z, z);
    const Eigen::Vector3d p_b = R_b_a * p_a + t_b_a;
    if (p_b.z() <= 0.1) continue;
    const auto project = [&](const Eigen::Vector3d& p) {
      return Eigen::Vector2d(v.K.fx * p.x() / p.z() + v.K.cx + noise(rng),
                             v.K.fy * p.y() / p.z() + v.K.cy + noise(rng));
    };
    sensor::PointObservation oa, ob;
    oa.point_id = ob.point_id = id;
    oa.uv = project(p_a);
    ob.uv = project(p_b);
    if (ob.uv.x() < 0 || ob.uv.x() > 752 || ob.uv.y() < 0 || ob.uv.y() > 480) continue;
    v.a.push_back(oa);
    v.b.push_back(ob);
  }
  return v;
}

// The translation tests on (the image default of plucker vo); Before(): the library default.
TwoViewOptions After() {
  TwoViewOptions o;
  o.min_translation_parallax_px = 5.0;
  o.min_triangulation_angle_deg = 0.5;
  o.max_depth_baselines = 1e4;
  return o;
}
TwoViewOptions Before() { return {}; }

TEST(TwoViewInitialization, PureRotationIsRefusedOverSeeds) {
  // A camera turning on the spot (3 deg, 0.7 px noise): no translation, no depth. Over 20 seeds
  // the start must refuse every one; the parallax after the essential matrix's rotation alone
  // let some through (printed: that is what the test guards against).
  const Eigen::Matrix3d R_b_a(
      Eigen::AngleAxisd(3.0 * M_PI / 180.0, Eigen::Vector3d(0.2, 1, 0.1).normalized()));
  int accepted_before = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const TwoViews v = MakeTwoViews(R_b_a, Eigen::Vector3d::Zero(), 2.0, 20.0, 0.7, seed);
    const TwoViewResult r = InitializeTwoView(v.K, v.a, v.b, After());
    EXPECT_FALSE(r.ok) << "seed " << seed << ": parallax " << r.parallax_px << " px";
    EXPECT_LT(r.translation_parallax_px, After().min_translation_parallax_px);
    accepted_before += InitializeTwoView(v.K, v.a, v.b, Before()).ok;
  }
  std::printf("pure rotation, 20 seeds: accepted by the parallax test alone %d\n", accepted_before);
}

TEST(TwoViewInitialization, ATinyBaselineIsRefusedARealOneAccepted) {
  // MH_05's start: 5 mm of translation at 2-10 m with 0.7 px noise and a small turn: refused.
  const Eigen::Matrix3d R_b_a(
      Eigen::AngleAxisd(1.0 * M_PI / 180.0, Eigen::Vector3d(1, 0.3, 0).normalized()));
  int accepted_before = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const TwoViews tiny =
        MakeTwoViews(R_b_a, Eigen::Vector3d(0.005, 0.0, 0.002), 2.0, 10.0, 0.7, seed);
    const TwoViewResult r = InitializeTwoView(tiny.K, tiny.a, tiny.b, After());
    EXPECT_FALSE(r.ok) << "seed " << seed << ": parallax " << r.parallax_px << " px";
    accepted_before += InitializeTwoView(tiny.K, tiny.a, tiny.b, Before()).ok;
  }
  std::printf("5 mm baseline, 20 seeds: accepted by the parallax test alone %d\n", accepted_before);
  // A real baseline: 0.5 m sideways at 3-14 m: accepted, with the right translation.
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const Eigen::Vector3d t_b_a(-0.5, 0.0, 0.05);
    const TwoViews real = MakeTwoViews(R_b_a, t_b_a, 3.0, 14.0, 0.7, seed);
    const TwoViewResult r = InitializeTwoView(real.K, real.a, real.b, After());
    ASSERT_TRUE(r.ok) << "seed " << seed << ": " << r.message;
    EXPECT_GT(r.translation_parallax_px, 5.0);
    EXPECT_GT(r.T_b_a.translation().dot(t_b_a.normalized()), 0.99);
    std::printf(
        "real baseline seed %u: parallax %.1f px, after the best rotation %.1f, angle %.2f deg\n",
        seed, r.parallax_px, r.translation_parallax_px, r.triangulation_angle_deg);
  }
}

}  // namespace
}  // namespace window
}  // namespace plucker
