#include "plucker/geometry/point_triangulation.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "plucker/geometry/geometry_test_utils.h"
#include "plucker/geometry/point_projection.h"

namespace plucker {
namespace {

using testing_utils::LookAt;
using testing_utils::TestK;

struct Scene {
  std::vector<SE3d> poses;
  std::vector<Eigen::Vector2d> uv;
};

Scene Observe(const Eigen::Vector3d& p_w, const std::vector<Eigen::Vector3d>& centres,
              std::mt19937_64* rng = nullptr, double sigma_px = 0.0) {
  Scene s;
  std::normal_distribution<double> noise(0.0, sigma_px);
  int i = 0;
  for (const Eigen::Vector3d& c : centres) {
    // Look slightly off the point so that it is not always at the principal point.
    const SE3d T = LookAt(c, p_w + Eigen::Vector3d(0.1 * i, -0.05 * i, 0.0), 0.3 * i);
    auto uv = ProjectPoint(TestK(), T, p_w);
    EXPECT_TRUE(uv.has_value());
    if (rng) *uv += Eigen::Vector2d(noise(*rng), noise(*rng));
    s.poses.push_back(T);
    s.uv.push_back(*uv);
    ++i;
  }
  return s;
}

std::vector<Eigen::Vector3d> Centres(int n, double baseline) {
  std::vector<Eigen::Vector3d> c;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    c.emplace_back(baseline * std::cos(a), 0.3 * baseline * std::sin(a), 0.1 * i);
  }
  return c;
}

TEST(PointTriangulation, ExactRecoveryNoiseFree) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Vector3d p_w(u(rng), u(rng), 8.0 + u(rng));
    for (int n : {2, 3, 7}) {
      const Scene s = Observe(p_w, Centres(n, 1.0));
      const auto r = TriangulatePoint(TestK(), s.poses, s.uv);
      ASSERT_TRUE(r.ok()) << r.message;
      EXPECT_LT((r.p_w - p_w).norm(), 1e-9 * (1 + p_w.norm()));
      EXPECT_LT(r.final_rms_px, 1e-8);
      EXPECT_GT(r.max_parallax_rad, 0.0);
    }
  }
}

TEST(PointTriangulation, NoisyErrorBoundAndRefinementHelps) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  double sum_sq_err = 0.0, sum_initial = 0.0, sum_final = 0.0;
  const int trials = 200;
  for (int trial = 0; trial < trials; ++trial) {
    const Eigen::Vector3d p_w(u(rng), u(rng), 6.0 + u(rng));
    const Scene s = Observe(p_w, Centres(5, 1.0), &rng, 1.0);
    const auto r = TriangulatePoint(TestK(), s.poses, s.uv);
    ASSERT_TRUE(r.ok()) << r.message;
    sum_sq_err += (r.p_w - p_w).squaredNorm();
    sum_initial += r.initial_rms_px;
    sum_final += r.final_rms_px;
    EXPECT_LE(r.final_rms_px, r.initial_rms_px + 1e-12);
    // Depth ~6 m, baseline ~2 m, f = 500: 1 px noise gives centimetres; 0.3 m is a safe bound.
    EXPECT_LT((r.p_w - p_w).norm(), 0.3);
  }
  const double rmse = std::sqrt(sum_sq_err / trials);
  EXPECT_LT(rmse, 0.08);
  EXPECT_LT(sum_final, sum_initial);
  // RMS over views of the 2D error norm: E|r|^2 = (5 * 2 - 3) / 5 sigma^2 = 1.4 sigma^2.
  EXPECT_NEAR(sum_final / trials, std::sqrt(1.4), 0.15);
}

TEST(PointTriangulation, TooFewViews) {
  const Scene s = Observe(Eigen::Vector3d(0, 0, 5), Centres(1, 1.0));
  const auto r = TriangulatePoint(TestK(), s.poses, s.uv);
  EXPECT_EQ(r.status, PointTriangulationStatus::kTooFewViews);
  PointTriangulationOptions o;
  o.min_views = 4;
  const Scene s3 = Observe(Eigen::Vector3d(0, 0, 5), Centres(3, 1.0));
  EXPECT_EQ(TriangulatePoint(TestK(), s3.poses, s3.uv, o).status,
            PointTriangulationStatus::kTooFewViews);
}

TEST(PointTriangulation, AllCamerasOnOneRay) {
  const Eigen::Vector3d p_w(1, 2, 10);
  const Eigen::Vector3d dir = Eigen::Vector3d(0.1, 0.2, 1).normalized();
  std::vector<Eigen::Vector3d> centres;
  for (int i = 0; i < 4; ++i) centres.push_back(p_w - (3.0 + i) * dir);
  const Scene s = Observe(p_w, centres);
  const auto r = TriangulatePoint(TestK(), s.poses, s.uv);
  EXPECT_EQ(r.status, PointTriangulationStatus::kSmallParallax) << r.message;
  EXPECT_LT(r.max_parallax_rad, 1e-6);
  EXPECT_FALSE(r.message.empty());
}

TEST(PointTriangulation, SmallParallaxReportsAngle) {
  // Baseline 2 cm at 10 m: ~0.11 deg < 1 deg.
  const Scene s = Observe(Eigen::Vector3d(0, 0, 10), Centres(2, 0.01));
  const auto r = TriangulatePoint(TestK(), s.poses, s.uv);
  EXPECT_EQ(r.status, PointTriangulationStatus::kSmallParallax);
  EXPECT_NEAR(r.max_parallax_rad, 0.02 / 10, 2e-4);
  PointTriangulationOptions o;
  o.min_parallax_deg = 0.05;
  EXPECT_TRUE(TriangulatePoint(TestK(), s.poses, s.uv, o).ok());
}

TEST(PointTriangulation, PointBehindACamera) {
  const Eigen::Vector3d p_w(0, 0, 5);
  Scene s = Observe(p_w, Centres(3, 1.0));
  // Rotate the last camera by pi about its y axis and mirror the pixel: the ray through the pixel
  // now points away from p_w, and the other rays meet in front of it... behind the camera.
  const SE3d T = s.poses[2];
  const SE3d T_flip(
      T.rotation() * Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY())),
      T.translation());
  // p_c of the flipped camera = (-x, y, -z): choose the pixel of the mirrored bearing (x, -y, z)
  // scaled by -1, i.e. the back-projected line through p_w seen from behind.
  const Eigen::Vector3d p_c = T_flip.Inverse() * p_w;  // z < 0
  ASSERT_LT(p_c.z(), 0);
  const Eigen::Vector2d xn = p_c.head<2>() / p_c.z();
  s.poses[2] = T_flip;
  s.uv[2] = TestK().ToPixel<double>(xn);
  const auto r = TriangulatePoint(TestK(), s.poses, s.uv);
  EXPECT_EQ(r.status, PointTriangulationStatus::kBehindCamera) << r.message;
}

TEST(PointTriangulation, InvalidInput) {
  Scene s = Observe(Eigen::Vector3d(0, 0, 5), Centres(3, 1.0));
  Scene bad = s;
  bad.uv[1].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(TriangulatePoint(TestK(), bad.poses, bad.uv).status,
            PointTriangulationStatus::kInvalidInput);
  bad = s;
  bad.uv.pop_back();
  EXPECT_EQ(TriangulatePoint(TestK(), bad.poses, bad.uv).status,
            PointTriangulationStatus::kInvalidInput);
  PinholeIntrinsics badK = TestK();
  badK.fy = -1;
  EXPECT_EQ(TriangulatePoint(badK, s.poses, s.uv).status, PointTriangulationStatus::kInvalidInput);
  // Zero baseline: every camera at the same centre.
  bad = s;
  for (SE3d& T : bad.poses) T = SE3d(T.rotation(), Eigen::Vector3d(1, 1, 1));
  const auto r = TriangulatePoint(TestK(), bad.poses, bad.uv);
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(r.p_w.allFinite());
}

TEST(PointTriangulation, NotConvergedWithOneIteration) {
  std::mt19937_64 rng(1);
  const Scene s = Observe(Eigen::Vector3d(0.5, -0.5, 6), Centres(4, 1.0), &rng, 3.0);
  PointTriangulationOptions o;
  o.max_iterations = 1;
  o.step_tolerance = 0;
  o.cost_tolerance = 0;
  const auto r = TriangulatePoint(TestK(), s.poses, s.uv, o);
  EXPECT_EQ(r.status, PointTriangulationStatus::kNotConverged) << r.message;
  EXPECT_TRUE(r.p_w.allFinite());
}

}  // namespace
}  // namespace plucker
