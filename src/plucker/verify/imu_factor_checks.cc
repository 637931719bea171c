// Jacobian checks of factors/imu_factor.h: analytic vs the autodiff twin (ambient, 1e-9) and vs
// central differences through PoseManifold::Plus and Euclidean steps (tangent, 1e-6).
//
// Each sample preintegrates random gyro and accelerometer readings at 200 Hz from a random
// linearisation bias, then places the states at j near the prediction from i (so the residual is
// small, as in an estimator) and the bias at i near the linearisation point.
// Curated first samples: 0 at rest with identity pose at i, 1 a single IMU sample, 2 a relative
// rotation near pi over the interval, 3 bias at i far from the linearisation point (0.05 rad/s,
// 0.5 m/s^2), 4 a 1 s interval, 5 states exactly on the prediction (zero residual).
#include <string>
#include <vector>

#include "plucker/factors/imu_factor.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/verify/checks.h"
#include "plucker/verify/cost_function_check.h"
#include "plucker/verify/imu_factor_sample.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace verify {

namespace {

ImuPreintegration MakePreintegration(Rng& rng, int i) {
  sensor::ImuBias bias_lin;
  bias_lin.gyro = RandomVector(rng, 0.01);
  bias_lin.accel = RandomVector(rng, 0.1);
  sensor::ImuModel noise;
  noise.gyro_noise_density *= Uniform(rng, 0.5, 5.0);
  noise.accel_noise_density *= Uniform(rng, 0.5, 5.0);
  ImuPreintegration p(bias_lin, noise);
  const int n = i == 1 ? 1 : i == 4 ? 200 : static_cast<int>(Uniform(rng, 2.0, 60.0));
  const double dt = 0.005;
  Eigen::Vector3d rate = RandomVector(rng, 1.0);
  if (i == 2) rate = RandomVector(rng, 1.0).normalized() * (M_PI - 1e-3) / (n * dt);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d gyro = i == 0 ? bias_lin.gyro : rate + RandomVector(rng, 0.1);
    const Eigen::Vector3d accel =
        i == 0 ? Eigen::Vector3d(bias_lin.accel + Eigen::Vector3d(0, 0, 9.81))
               : Eigen::Vector3d(Eigen::Vector3d(0, 0, 9.81) + RandomVector(rng, 3.0));
    p.Integrate(dt, gyro, accel);
  }
  return p;
}

}  // namespace

ImuFactorSample MakeImuFactorSample(Rng& rng, int i) {
  ImuFactorSample c;
  c.preintegration = MakePreintegration(rng, i);
  const sensor::ImuBias& lin = c.preintegration.BiasLinearisation();
  NavState s_i;
  const SE3d T_i = i == 0 ? SE3d() : RandomPose(rng, 10.0);
  s_i.R_w_b = T_i.RotationMatrix();
  s_i.p_w = T_i.translation();
  s_i.v_w = i == 0 ? Eigen::Vector3d::Zero() : RandomVector(rng, 3.0);
  sensor::ImuBias b_i = lin;
  if (i != 5) {
    b_i.gyro += RandomVector(rng, i == 3 ? 0.05 : 1e-3);
    b_i.accel += RandomVector(rng, i == 3 ? 0.5 : 1e-2);
  }
  const NavState s_j = c.preintegration.Predict(s_i, b_i, kImuSampleGravity);
  const double e = i == 5 ? 0.0 : 1.0;
  c.T_w_b_i = T_i;
  c.T_w_b_j = SE3d(Eigen::Quaterniond(s_j.R_w_b) * ExpSO3<double>(RandomVector(rng, 1e-3 * e)),
                   s_j.p_w + RandomVector(rng, 1e-2 * e));
  c.v_i = s_i.v_w;
  c.v_j = s_j.v_w + RandomVector(rng, 1e-2 * e);
  c.bias_i << b_i.gyro, b_i.accel;
  c.bias_j = c.bias_i;
  c.bias_j.head<3>() += RandomVector(rng, 1e-4 * e);
  c.bias_j.tail<3>() += RandomVector(rng, 1e-3 * e);
  return c;
}

namespace {

std::string Describe(int i) {
  static const char* kNames[] = {"at rest, identity pose", "one IMU sample",
                                 "rotation near pi",       "bias far from linearisation",
                                 "1 s interval",           "zero residual"};
  return i < 6 ? kNames[i] : "random";
}

void AddPose(const SE3d& T, const PoseManifold* manifold, CostFunctionSample* c) {
  c->x.emplace_back(7);
  T.ToParameters(c->x.back().data());
  c->manifolds.push_back(manifold);
}

void AddVector(const Eigen::VectorXd& v, CostFunctionSample* c) {
  c->x.push_back(v);
  c->manifolds.push_back(nullptr);
}

}  // namespace

std::vector<NamedJacobianCheck> ImuFactorJacobianChecks() {
  const std::string name = "factor.imu.Preintegration";
  return {{name, [name](const JacobianCheckOptions& o) {
             const PoseManifold pose;
             return RunCostFunctionCheck(name, 401, o, [&](Rng& rng, int i) {
               const ImuFactorSample s = MakeImuFactorSample(rng, i);
               CostFunctionSample c;
               c.analytic.reset(ImuFactor::Create(s.preintegration, kImuSampleGravity));
               c.autodiff.reset(ImuFactor::CreateAutoDiff(s.preintegration, kImuSampleGravity));
               AddPose(s.T_w_b_i, &pose, &c);
               AddVector(s.v_i, &c);
               AddVector(s.bias_i, &c);
               AddPose(s.T_w_b_j, &pose, &c);
               AddVector(s.v_j, &c);
               AddVector(s.bias_j, &c);
               c.what = Describe(i);
               return c;
             });
           }}};
}

}  // namespace verify
}  // namespace plucker
