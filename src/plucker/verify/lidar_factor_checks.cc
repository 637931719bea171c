// Jacobian checks of factors/lidar_factors.h: analytic vs the autodiff twin (ambient, 1e-9) and vs
// central differences through PoseManifold::Plus (tangent, 1e-6).
//
// Curated first samples: 0 the point exactly on the plane / edge line (residual zero), 1 a
// rotation of exactly pi, 2 a rotation pi - 1e-7, 3 edge points 1e-6 m apart (nearly coincident),
// 4 a scan point 100 m away, 5 the identity pose, 6 a small sigma (0.01 m). For the scalar edge
// factor sample 0 puts the point 1 cm from the line instead: on the line it has its kink (the
// distance is zero up to rounding and the gradient direction is noise; the zero-distance
// behaviour is tested in factors_lidar_factors_test).
#include <string>
#include <vector>

#include "plucker/factors/lidar_factors.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/verify/checks.h"
#include "plucker/verify/cost_function_check.h"
#include "plucker/verify/lidar_comparison_factors.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace verify {

namespace {

struct LidarSample {
  SE3d T_w_s;
  Eigen::Vector3d p_s, a_w, b_w, m_w, q_w;
  double sigma = 1.0;
};

// A random configuration; `on_feature` puts p_w exactly on the edge line and on the plane.
LidarSample MakeSample(Rng& rng, int i) {
  LidarSample s;
  switch (i) {
    case 1:
      s.T_w_s = SE3d(RotationNearPi(rng, 0.0), RandomVector(rng, 5.0));
      break;
    case 2:
      s.T_w_s = SE3d(RotationNearPi(rng, 1e-7), RandomVector(rng, 5.0));
      break;
    case 5:
      s.T_w_s = SE3d();
      break;
    default:
      s.T_w_s = RandomPose(rng, 5.0);
  }
  s.sigma = i == 6 ? 0.01 : Uniform(rng, 0.05, 2.0);
  s.p_s = i == 4 ? RandomUnitVector(rng) * 100.0 : RandomVector(rng, 10.0);
  const Eigen::Vector3d p_w = s.T_w_s * s.p_s;
  // Features near the point (as real correspondences are), 0.05 .. 1 m off.
  const Eigen::Vector3d dir = RandomUnitVector(rng);
  const double length = i == 3 ? 1e-6 : Uniform(rng, 0.1, 2.0);
  s.a_w = p_w + RandomVector(rng, 1.0);
  if (i == 0) s.a_w = p_w - Uniform(rng, -1.0, 1.0) * dir;  // p_w on the line through a, b
  s.b_w = s.a_w + length * dir;
  s.m_w = RandomUnitVector(rng);
  s.q_w = p_w + RandomVector(rng, 1.0);
  if (i == 0) {  // p_w on the plane: q_w = p_w + a vector orthogonal to m
    const Eigen::Vector3d v = RandomVector(rng, 1.0);
    s.q_w = p_w + (v - v.dot(s.m_w) * s.m_w);
  }
  return s;
}

std::string Describe(int i) {
  static const char* kNames[] = {"on feature",      "rotation pi",    "rotation pi - 1e-7",
                                 "a, b 1e-6 apart", "point at 100 m", "identity pose",
                                 "sigma 0.01"};
  return i < 7 ? kNames[i] : "random";
}

// The check of the factor made by create / create_autodiff(p_s, feature_a, feature_b, sigma) at
// the pose T_w_s; `plane` passes (m_w, q_w), otherwise (a_w, b_w). `near_instead_of_on_feature`
// moves sample 0 to 1 cm from the line.
template <typename Create>
NamedJacobianCheck LidarFactorCheck(const std::string& name, std::uint64_t seed, bool plane,
                                    bool near_instead_of_on_feature, Create create,
                                    Create create_autodiff) {
  return {name, [=](const JacobianCheckOptions& o) {
            const PoseManifold pose;
            return RunCostFunctionCheck(name, seed, o, [&](Rng& rng, int i) {
              LidarSample s = MakeSample(rng, i);
              CostFunctionSample c;
              c.what = Describe(i);
              if (near_instead_of_on_feature && i == 0) {
                // 1 cm sideways: close to the kink, yet smooth at the difference step.
                const Eigen::Vector3d side = (s.b_w - s.a_w).normalized().unitOrthogonal() * 0.01;
                s.a_w += side;
                s.b_w += side;
                c.what = "1 cm from the line";
              }
              const Eigen::Vector3d& f1 = plane ? s.m_w : s.a_w;
              const Eigen::Vector3d& f2 = plane ? s.q_w : s.b_w;
              c.analytic.reset(create(s.p_s, f1, f2, s.sigma));
              c.autodiff.reset(create_autodiff(s.p_s, f1, f2, s.sigma));
              c.x = {Eigen::VectorXd(7)};
              s.T_w_s.ToParameters(c.x[0].data());
              c.manifolds = {&pose};
              c.inputs = {{"p_s", s.p_s},
                          {plane ? "m_w" : "a_w", f1},
                          {plane ? "q_w" : "b_w", f2},
                          {"sigma", Eigen::VectorXd::Constant(1, s.sigma)}};
              return c;
            });
          }};
}

}  // namespace

std::vector<NamedJacobianCheck> LidarFactorJacobianChecks() {
  return {
      LidarFactorCheck("factor.lidar.PointToPlane", 101, true, false, &PointToPlaneFactor::Create,
                       &PointToPlaneFactor::CreateAutoDiff),
      LidarFactorCheck("factor.lidar.PointToEdge", 102, false, false, &PointToEdgeFactor::Create,
                       &PointToEdgeFactor::CreateAutoDiff),
      LidarFactorCheck("factor.lidar.PointToEdge2", 103, false, false, &PointToEdge2Factor::Create,
                       &PointToEdge2Factor::CreateAutoDiff),
      LidarFactorCheck("factor.lidar.PointToEdgeScalar", 104, false, true,
                       &PointToEdgeScalarFactor::Create, &PointToEdgeScalarFactor::CreateAutoDiff)};
}

}  // namespace verify
}  // namespace plucker
