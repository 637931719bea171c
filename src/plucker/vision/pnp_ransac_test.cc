// PnpRansac and EssentialPose (vision/pnp_ransac.h) on synthetic views with a known pose: the
// pose is recovered, outliers are flagged, and bad input gives a status, never an exception.
#include "plucker/vision/pnp_ransac.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace plucker {
namespace vision {
namespace {

PinholeIntrinsics TestK() {
  PinholeIntrinsics K;
  K.fx = 450.0;
  K.fy = 455.0;
  K.cx = 320.0;
  K.cy = 240.0;
  return K;
}

// Points in front of both cameras: camera a at the origin, b at T_b_a.
struct Scene {
  std::vector<Eigen::Vector3d> points_a;  // in frame a (= world)
  SE3d T_b_a;
};

Scene MakeScene(int n, std::mt19937* rng) {
  std::uniform_real_distribution<double> xy(-2.0, 2.0), z(4.0, 9.0);
  Scene s;
  for (int i = 0; i < n; ++i) s.points_a.emplace_back(xy(*rng), xy(*rng), z(*rng));
  s.T_b_a = SE3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.08, Eigen::Vector3d(0.2, 1.0, -0.1).normalized())),
      Eigen::Vector3d(0.6, -0.1, 0.15));
  return s;
}

Eigen::Vector2d Pixel(const PinholeIntrinsics& K, const Eigen::Vector3d& p_c) {
  return {K.fx * p_c.x() / p_c.z() + K.cx, K.fy * p_c.y() / p_c.z() + K.cy};
}

TEST(PnpRansac, RecoversThePoseAndFlagsOutliers) {
  std::mt19937 rng(7);
  const Scene s = MakeScene(80, &rng);
  const PinholeIntrinsics K = TestK();
  std::vector<Eigen::Vector2d> uv;
  for (const auto& p : s.points_a) uv.push_back(Pixel(K, s.T_b_a * p));
  for (int i = 0; i < 10; ++i) uv[i] += Eigen::Vector2d(40.0 + i, -35.0);  // outliers
  for (PnpSolver solver : {PnpSolver::kEpnp, PnpSolver::kAp3p}) {
    PnpRansacOptions o;
    o.solver = solver;
    o.iterations = 500;
    o.threshold_px = 2.0;
    const PnpRansacResult r = PnpRansac(s.points_a, uv, K, o);
    ASSERT_TRUE(r.ok()) << r.message;
    EXPECT_LT((r.T_c_w.translation() - s.T_b_a.translation()).norm(), 1e-6);
    EXPECT_LT(r.T_c_w.rotation().angularDistance(s.T_b_a.rotation()), 1e-6);
    EXPECT_EQ(r.inliers.size(), 70u);
    for (int i : r.inliers) EXPECT_GE(i, 10);
  }
}

TEST(PnpRansac, BadInputIsAStatusNotAnException) {
  const PinholeIntrinsics K = TestK();
  PnpRansacOptions o;
  // Too few correspondences for the options.
  std::vector<Eigen::Vector3d> p = {{0, 0, 5}, {1, 0, 5}, {0, 1, 5}};
  std::vector<Eigen::Vector2d> uv = {{320, 240}, {410, 240}, {320, 331}};
  EXPECT_EQ(PnpRansac(p, uv, K, o).status, PnpStatus::kTooFewCorrespondences);
  // Sizes that disagree.
  uv.pop_back();
  EXPECT_EQ(PnpRansac(p, uv, K, o).status, PnpStatus::kTooFewCorrespondences);
  // Three points handed to OpenCV regardless: it throws inside, reported as a status.
  uv.emplace_back(320, 331);
  o.min_correspondences = 0;
  PnpRansacResult r;
  EXPECT_NO_THROW(r = PnpRansac(p, uv, K, o));
  EXPECT_FALSE(r.ok());
  EXPECT_FALSE(r.message.empty());
  // Non-finite observations.
  std::mt19937 rng(3);
  const Scene s = MakeScene(20, &rng);
  std::vector<Eigen::Vector2d> nan(20, Eigen::Vector2d::Constant(std::nan("")));
  o.min_correspondences = 6;
  EXPECT_NO_THROW(r = PnpRansac(s.points_a, nan, K, o));
  EXPECT_FALSE(r.ok());
}

TEST(EssentialPose, RecoversTheRelativePose) {
  std::mt19937 rng(11);
  const Scene s = MakeScene(60, &rng);
  std::vector<Eigen::Vector2d> xa, xb;
  for (const auto& p : s.points_a) {
    const Eigen::Vector3d pb = s.T_b_a * p;
    xa.push_back(p.hnormalized());
    xb.push_back(pb.hnormalized());
  }
  xb[0] += Eigen::Vector2d(0.05, 0.03);  // one outlier
  EssentialPoseOptions o;
  o.threshold = 1.0 / 450.0;
  const EssentialPoseResult r = EssentialPose(xa, xb, o);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_LT((r.R_b_a - s.T_b_a.RotationMatrix()).norm(), 1e-6);
  EXPECT_LT((r.t_b_a - s.T_b_a.translation().normalized()).norm(), 1e-6);
  EXPECT_EQ(r.inliers, 59);
  ASSERT_EQ(r.inlier_mask.size(), xa.size());
  EXPECT_EQ(r.inlier_mask[0], 0);
}

TEST(EssentialPose, DegenerateInputIsAStatus) {
  EssentialPoseOptions o;
  std::vector<Eigen::Vector2d> x(4, Eigen::Vector2d(0.1, 0.2));
  EXPECT_EQ(EssentialPose(x, x, o).status, EssentialPoseStatus::kTooFewMatches);
  std::vector<Eigen::Vector2d> a = {{0.1, 0.2}}, b;
  EXPECT_EQ(EssentialPose(a, b, o).status, EssentialPoseStatus::kTooFewMatches);
  // Every match the same point and no motion: no model, no exception.
  std::vector<Eigen::Vector2d> same(12, Eigen::Vector2d(0.1, 0.2));
  EssentialPoseResult r;
  EXPECT_NO_THROW(r = EssentialPose(same, same, o));
  EXPECT_FALSE(r.ok() && r.inliers > 0);
}

}  // namespace
}  // namespace vision
}  // namespace plucker
