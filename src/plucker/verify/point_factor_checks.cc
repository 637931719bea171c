// Jacobian checks of factors/point_reprojection_factor.h: analytic vs the autodiff twin (ambient,
// 1e-9) and vs central differences through PoseManifold::Plus and Euclidean point steps (tangent,
// 1e-6).
//
// Curated first samples: 0 identity pose(s), 1 a rotation of exactly pi, 2 a rotation pi - 1e-7,
// 3 a point 100 m away, 4 a point 5 cm in front of the camera, 5 a point on the optical axis,
// 6 a point far off-axis (x/z = 2), 7 an identity extrinsic (VI only matters).
#include <memory>

#include "plucker/factors/point_reprojection_factor.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/verify/checks.h"
#include "plucker/verify/cost_function_check.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace verify {

namespace {

struct PointSample {
  PinholeIntrinsics K;
  SE3d T_w_b, T_b_c;  // T_w_c = T_w_b * T_b_c
  Eigen::Vector3d p_w;
  Eigen::Vector2d uv;
  Eigen::Matrix2d sqrt_information;
};

SE3d SampleRotationCase(Rng& rng, int i, double translation_scale) {
  switch (i) {
    case 0:
      return SE3d();
    case 1:
      return SE3d(RotationNearPi(rng, 0.0), RandomVector(rng, translation_scale));
    case 2:
      return SE3d(RotationNearPi(rng, 1e-7), RandomVector(rng, translation_scale));
    default:
      return RandomPose(rng, translation_scale);
  }
}

PointSample MakeSample(Rng& rng, int i) {
  PointSample s;
  s.K.fx = Uniform(rng, 300.0, 800.0);
  s.K.fy = s.K.fx * Uniform(rng, 0.95, 1.05);
  s.K.cx = Uniform(rng, 300.0, 340.0);
  s.K.cy = Uniform(rng, 220.0, 260.0);
  s.T_w_b = SampleRotationCase(rng, i, 5.0);
  s.T_b_c = i == 0 || i == 7 ? SE3d() : SampleRotationCase(rng, i, 0.2);
  // The point in camera coordinates, then in the world.
  double depth = Uniform(rng, 0.5, 20.0);
  if (i == 3) depth = 100.0;
  if (i == 4) depth = 0.05;
  Eigen::Vector3d p_c(Uniform(rng, -0.7, 0.7) * depth, Uniform(rng, -0.5, 0.5) * depth, depth);
  if (i == 5) p_c.head<2>().setZero();
  if (i == 6) p_c.x() = 2.0 * depth;
  s.p_w = (s.T_w_b * s.T_b_c) * p_c;
  s.uv = s.K.ToPixel<double>(p_c.head<2>() / p_c.z()) +
         Eigen::Vector2d(RandomVector(rng, 3.0).head<2>());
  const double inv_sigma = 1.0 / Uniform(rng, 0.5, 2.0);
  s.sqrt_information << inv_sigma, Uniform(rng, -0.2, 0.2), 0.0, inv_sigma * Uniform(rng, 0.8, 1.2);
  return s;
}

std::string Describe(int i) {
  static const char* kNames[] = {"identity poses",   "rotation pi",       "rotation pi - 1e-7",
                                 "point at 100 m",   "depth 5 cm",        "on the optical axis",
                                 "off-axis x/z = 2", "identity extrinsic"};
  return i < 8 ? kNames[i] : "random";
}

JacobianCheckStats CheckPointReprojection(const JacobianCheckOptions& o) {
  JacobianCheckStats stats;
  stats.name = "factor.point.Reprojection";
  Rng rng(o.seed + 201);
  PoseManifold pose;
  for (int i = 0; i < o.samples; ++i) {
    const PointSample s = MakeSample(rng, i);
    const std::unique_ptr<ceres::CostFunction> an(
        PointReprojectionFactor::Create(s.K, s.uv, s.sqrt_information));
    const std::unique_ptr<ceres::CostFunction> ad(
        PointReprojectionFactor::CreateAutoDiff(s.K, s.uv, s.sqrt_information));
    Eigen::VectorXd x(7);
    (s.T_w_b * s.T_b_c).ToParameters(x.data());
    if (!AddCostFunctionSample(*an, *ad, {&pose, nullptr}, {x, Eigen::VectorXd(s.p_w)}, &stats,
                               Describe(i))) {
      ++stats.skipped;
    }
  }
  return stats;
}

JacobianCheckStats CheckPointReprojectionVI(const JacobianCheckOptions& o) {
  JacobianCheckStats stats;
  stats.name = "factor.point.ReprojectionVI";
  Rng rng(o.seed + 202);
  PoseManifold pose;
  for (int i = 0; i < o.samples; ++i) {
    const PointSample s = MakeSample(rng, i);
    const std::unique_ptr<ceres::CostFunction> an(
        PointReprojectionFactorVI::Create(s.K, s.uv, s.sqrt_information));
    const std::unique_ptr<ceres::CostFunction> ad(
        PointReprojectionFactorVI::CreateAutoDiff(s.K, s.uv, s.sqrt_information));
    Eigen::VectorXd x_wb(7), x_bc(7);
    s.T_w_b.ToParameters(x_wb.data());
    s.T_b_c.ToParameters(x_bc.data());
    if (!AddCostFunctionSample(*an, *ad, {&pose, &pose, nullptr},
                               {x_wb, x_bc, Eigen::VectorXd(s.p_w)}, &stats, Describe(i))) {
      ++stats.skipped;
    }
  }
  return stats;
}

}  // namespace

std::vector<NamedJacobianCheck> PointFactorJacobianChecks() {
  return {{"factor.point.Reprojection", CheckPointReprojection},
          {"factor.point.ReprojectionVI", CheckPointReprojectionVI}};
}

}  // namespace verify
}  // namespace plucker
