// Jacobian checks of factors/point_reprojection_factor.h: analytic vs the autodiff twin (ambient,
// 1e-9) and vs central differences through PoseManifold::Plus and Euclidean point steps (tangent,
// 1e-6).
//
// Curated first samples: 0 identity pose(s), 1 a rotation of exactly pi, 2 a rotation pi - 1e-7,
// 3 a point 100 m away, 4 a point 5 cm in front of the camera, 5 a point on the optical axis,
// 6 a point far off-axis (x/z = 2), 7 an identity extrinsic (VI only matters). The time-offset
// check (factors/time_offset_factor.h) adds the image velocity and td: zero velocity on samples
// 0 and 8, td = 0 on samples 1 and 9, both random otherwise.
#include <string>
#include <vector>

#include "plucker/factors/held_extrinsic_factor.h"
#include "plucker/factors/point_reprojection_factor.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/factors/time_offset_factor.h"
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

// The sample's measurement, named as the Python factories' arguments.
std::vector<std::pair<std::string, Eigen::VectorXd>> Inputs(const PointSample& s) {
  const Eigen::Matrix2d& S = s.sqrt_information;
  return {{"K", Eigen::Vector4d(s.K.fx, s.K.fy, s.K.cx, s.K.cy)},
          {"uv", s.uv},
          {"sqrt_information", Eigen::Vector4d(S(0, 0), S(0, 1), S(1, 0), S(1, 1))}};
}

std::string Describe(int i) {
  static const char* kNames[] = {"identity poses",   "rotation pi",       "rotation pi - 1e-7",
                                 "point at 100 m",   "depth 5 cm",        "on the optical axis",
                                 "off-axis x/z = 2", "identity extrinsic"};
  return i < 8 ? kNames[i] : "random";
}

// The check of the factor made by create / create_autodiff: a pose (T_w_c, or T_w_b and T_b_c
// with vi) and the world point.
// With `held` (the stereo right camera's factor, window/window_stereo.cc): the VI factor with
// T_b_c held as the extrinsic T_c0_c1 (HeldExtrinsicFactor), on (T_w_b = T_w_c0, p_w).
template <typename Create>
NamedJacobianCheck PointFactorCheck(const std::string& name, std::uint64_t seed, bool vi,
                                    Create create, Create create_autodiff, bool held = false) {
  return {name, [=](const JacobianCheckOptions& o) {
            const PoseManifold pose;
            return RunCostFunctionCheck(name, seed, o, [&](Rng& rng, int i) {
              const PointSample s = MakeSample(rng, i);
              CostFunctionSample c;
              c.analytic.reset(create(s.K, s.uv, s.sqrt_information));
              c.autodiff.reset(create_autodiff(s.K, s.uv, s.sqrt_information));
              if (held) {
                c.analytic.reset(new HeldExtrinsicFactor<3>(c.analytic.release(), s.T_b_c));
                c.autodiff.reset(new HeldExtrinsicFactor<3>(c.autodiff.release(), s.T_b_c));
              }
              const std::vector<SE3d> poses = held ? std::vector<SE3d>{s.T_w_b}
                                                   : (vi ? std::vector<SE3d>{s.T_w_b, s.T_b_c}
                                                         : std::vector<SE3d>{s.T_w_b * s.T_b_c});
              for (const SE3d& T : poses) {
                c.x.emplace_back(7);
                T.ToParameters(c.x.back().data());
                c.manifolds.push_back(&pose);
              }
              c.x.push_back(s.p_w);
              c.manifolds.push_back(nullptr);
              c.what = Describe(i);
              c.inputs = Inputs(s);
              return c;
            });
          }};
}

// The image velocity (px/s) and td (s) of sample i of a time-offset check.
void SampleTimeOffset(Rng& rng, int i, Eigen::Vector2d* v, double* td) {
  *v = Eigen::Vector2d(Uniform(rng, -300.0, 300.0), Uniform(rng, -300.0, 300.0));
  *td = Uniform(rng, -0.05, 0.05);
  if (i == 0 || i == 8) v->setZero();
  if (i == 1 || i == 9) *td = 0.0;
}

// PointReprojectionFactorVITimeOffset: the VI sample, its velocity and the td block (Euclidean,
// before the point).
NamedJacobianCheck PointTimeOffsetCheck(const std::string& name, std::uint64_t seed) {
  return {name, [=](const JacobianCheckOptions& o) {
            const PoseManifold pose;
            return RunCostFunctionCheck(name, seed, o, [&](Rng& rng, int i) {
              const PointSample s = MakeSample(rng, i);
              Eigen::Vector2d v;
              double td;
              SampleTimeOffset(rng, i, &v, &td);
              CostFunctionSample c;
              c.analytic.reset(
                  PointReprojectionFactorVITimeOffset::Create(s.K, s.uv, v, s.sqrt_information));
              c.autodiff.reset(PointReprojectionFactorVITimeOffset::CreateAutoDiff(
                  s.K, s.uv, v, s.sqrt_information));
              for (const SE3d& T : {s.T_w_b, s.T_b_c}) {
                c.x.emplace_back(7);
                T.ToParameters(c.x.back().data());
                c.manifolds.push_back(&pose);
              }
              c.x.push_back(Eigen::VectorXd::Constant(1, td));
              c.x.push_back(s.p_w);
              c.manifolds.insert(c.manifolds.end(), 2, nullptr);
              c.inputs = Inputs(s);
              c.inputs.emplace_back("uv_velocity", v);
              c.what = Describe(i) + (i == 0 || i == 8 ? ", zero velocity" : "") +
                       (i == 1 || i == 9 ? ", td = 0" : "");
              return c;
            });
          }};
}

}  // namespace

std::vector<NamedJacobianCheck> PointFactorJacobianChecks() {
  return {
      PointFactorCheck("factor.point.Reprojection", 201, false, &PointReprojectionFactor::Create,
                       &PointReprojectionFactor::CreateAutoDiff),
      PointFactorCheck("factor.point.ReprojectionVI", 202, true, &PointReprojectionFactorVI::Create,
                       &PointReprojectionFactorVI::CreateAutoDiff),
      PointTimeOffsetCheck("factor.point.ReprojectionVI.time_offset", 203),
      PointFactorCheck("factor.point.StereoRight", 204, true, &PointReprojectionFactorVI::Create,
                       &PointReprojectionFactorVI::CreateAutoDiff, true)};
}

}  // namespace verify
}  // namespace plucker
