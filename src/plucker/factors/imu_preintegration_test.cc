#include "plucker/factors/imu_preintegration.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <vector>

#include "plucker/factors/imu_factor.h"
#include "plucker/geometry/so3.h"
#include "plucker/sim/trajectory_test_utils.h"
#include "plucker/verify/checks.h"

namespace plucker {
namespace {

const Eigen::Vector3d kGravity(0.0, 0.0, -9.81);

sim::Trajectory TestTrajectory() { return sim::ExcitingTestTrajectory(10.0); }

NavState TruthAt(const sim::Trajectory& traj, double t) {
  return {traj.R_w_b(t), traj.position_w(t), traj.velocity_w(t)};
}

// Noise-free readings at rate_hz integrated over [t0, t0 + duration).
ImuPreintegration Preintegrate(const sim::Trajectory& traj, double rate_hz, double t0,
                               double duration, const sensor::ImuBias& bias) {
  ImuPreintegration p(bias, sensor::ImuModel());
  const double dt = 1.0 / rate_hz;
  const int first = static_cast<int>(std::lround(t0 * rate_hz));
  const int n = static_cast<int>(std::lround(duration * rate_hz));
  const std::vector<sensor::ImuSample> samples =
      sim::NoiseFreeImu(traj, rate_hz, bias.gyro, bias.accel, kGravity);
  for (int k = first; k < first + n; ++k) p.Integrate(dt, samples[k].gyro, samples[k].accel);
  return p;
}

double PositionError(const ImuPreintegration& p, const sim::Trajectory& traj, double t0,
                     const sensor::ImuBias& bias) {
  const NavState j = p.Predict(TruthAt(traj, t0), bias, kGravity);
  return (j.p_w - traj.position_w(t0 + p.Dt())).norm();
}

// Held samples (the reading at the start of every step): first order.
TEST(ImuPreintegration, HeldSamplesConvergeAtFirstOrder) {
  const sim::Trajectory traj = TestTrajectory();
  sensor::ImuBias bias;
  bias.gyro << 0.01, -0.02, 0.005;
  bias.accel << 0.1, 0.05, -0.08;
  const double t0 = 2.0, duration = 1.0;
  const ImuPreintegration coarse = Preintegrate(traj, 200.0, t0, duration, bias);
  const ImuPreintegration fine = Preintegrate(traj, 1000.0, t0, duration, bias);
  ASSERT_EQ(coarse.NumSamples(), 200);
  ASSERT_EQ(fine.NumSamples(), 1000);
  const double e_coarse = PositionError(coarse, traj, t0, bias);
  const double e_fine = PositionError(fine, traj, t0, bias);
  EXPECT_LT(e_coarse, 0.02);                 // 2 cm after 1 s of motion at 200 Hz
  EXPECT_NEAR(e_coarse / e_fine, 5.0, 1.0);  // first order: 5x the rate, 1/5 the error
  // The rotation is exact for constant rates; over a smooth motion it converges too.
  const NavState j = fine.Predict(TruthAt(traj, t0), bias, kGravity);
  EXPECT_LT(LogSO3<double>(Eigen::Quaterniond(traj.R_w_b(t0 + 1.0).transpose() * j.R_w_b)).norm(),
            1e-3);
}

// The sample stream with the mean readings of each step: second order.
TEST(ImuPreintegration, SampleStreamConvergesAtSecondOrder) {
  const sim::Trajectory traj = TestTrajectory();
  sensor::ImuBias bias;
  bias.gyro << 0.01, -0.02, 0.005;
  bias.accel << 0.1, 0.05, -0.08;
  const double t0 = 2.0, t1 = 3.0;
  double error[2];
  for (int r = 0; r < 2; ++r) {
    const ImuPreintegration p = PreintegrateSamples(
        sim::NoiseFreeImu(traj, r == 0 ? 100.0 : 500.0, bias.gyro, bias.accel, kGravity), t0, t1,
        bias, sensor::ImuModel());
    EXPECT_NEAR(p.Dt(), 1.0, 1e-12);
    error[r] = PositionError(p, traj, t0, bias);
  }
  EXPECT_LT(error[0], 2e-3);             // 2 mm after 1 s at 100 Hz
  EXPECT_GT(error[0] / error[1], 15.0);  // 5x the rate: 1/25 the error at second order
}

TEST(ImuPreintegration, SampleStreamRefusesAnUncoveredInterval) {
  std::vector<sensor::ImuSample> imu(3);
  for (int k = 0; k < 3; ++k) imu[k].t = 0.01 * k;
  EXPECT_THROW(PreintegrateSamples(imu, 0.0, 0.03, sensor::ImuBias(), sensor::ImuModel()),
               std::invalid_argument);
  EXPECT_THROW(PreintegrateSamples(imu, 0.01, 0.01, sensor::ImuBias(), sensor::ImuModel()),
               std::invalid_argument);
  // A sub-interval cut at both ends: 0.005 .. 0.015 s.
  EXPECT_NEAR(PreintegrateSamples(imu, 0.005, 0.015, sensor::ImuBias(), sensor::ImuModel()).Dt(),
              0.01, 1e-15);
}

std::vector<Eigen::Matrix<double, 6, 1>> RandomReadings(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Matrix<double, 6, 1>> out(n);
  for (auto& s : out) {
    s << u(rng), u(rng), u(rng), 3 * u(rng), 3 * u(rng), 9.81 + 3 * u(rng);
  }
  return out;
}

ImuPreintegration Integrate(const std::vector<Eigen::Matrix<double, 6, 1>>& readings,
                            const sensor::ImuBias& bias) {
  ImuPreintegration p(bias, sensor::ImuModel());
  for (const auto& s : readings) p.Integrate(0.005, s.head<3>(), s.tail<3>());
  return p;
}

// The bias Jacobians against central differences of a full re-integration at b +- h e_k.
TEST(ImuPreintegration, BiasJacobiansMatchCentralDifferences) {
  const auto readings = RandomReadings(100, 3);
  sensor::ImuBias b;
  b.gyro << 0.02, -0.01, 0.03;
  b.accel << 0.2, -0.1, 0.05;
  const ImuPreintegration p = Integrate(readings, b);
  const double h = 1e-6;
  int compared = 0;
  for (int k = 0; k < 6; ++k) {
    sensor::ImuBias plus = b, minus = b;
    (k < 3 ? plus.gyro : plus.accel)(k % 3) += h;
    (k < 3 ? minus.gyro : minus.accel)(k % 3) -= h;
    const ImuPreintegration pp = Integrate(readings, plus), pm = Integrate(readings, minus);
    const Eigen::Vector3d dv = (pp.DeltaV() - pm.DeltaV()) / (2 * h);
    const Eigen::Vector3d dp = (pp.DeltaP() - pm.DeltaP()) / (2 * h);
    const Eigen::Vector3d dv_a = k < 3 ? p.d_v_d_bg().col(k) : p.d_v_d_ba().col(k - 3);
    const Eigen::Vector3d dp_a = k < 3 ? p.d_p_d_bg().col(k) : p.d_p_d_ba().col(k - 3);
    EXPECT_LT((dv - dv_a).norm(), 1e-6 * (1 + dv_a.norm())) << "bias component " << k;
    EXPECT_LT((dp - dp_a).norm(), 1e-6 * (1 + dp_a.norm())) << "bias component " << k;
    if (k < 3) {
      // DR(b + h e) = DR Exp(dR_dbg h e): the rotation difference in the tangent at DR.
      const Eigen::Vector3d dR =
          (LogSO3<double>(Eigen::Quaterniond(p.DeltaR().transpose() * pp.DeltaR())) -
           LogSO3<double>(Eigen::Quaterniond(p.DeltaR().transpose() * pm.DeltaR()))) /
          (2 * h);
      EXPECT_LT((dR - p.d_R_d_bg().col(k)).norm(), 1e-6 * (1 + dR.norm()));
    }
    ++compared;
  }
  EXPECT_EQ(compared, 6);
}

TEST(ImuPreintegration, RepropagateEqualsIntegratingAtTheNewBias) {
  const auto readings = RandomReadings(50, 5);
  ImuPreintegration p = Integrate(readings, sensor::ImuBias());
  sensor::ImuBias b;
  b.gyro << 0.1, 0.0, -0.1;
  b.accel << 0.5, 0.2, 0.0;
  p.Repropagate(b);
  const ImuPreintegration q = Integrate(readings, b);
  EXPECT_EQ(p.NumSamples(), 50);
  EXPECT_LT((p.DeltaR() - q.DeltaR()).norm(), 1e-15);
  EXPECT_LT((p.DeltaP() - q.DeltaP()).norm(), 1e-15);
  EXPECT_LT((p.JointCovariance() - q.JointCovariance()).norm(), 1e-15 * q.JointCovariance().norm());
}

// The propagated covariance against the scatter of 2000 noisy integrations of the same motion.
TEST(ImuPreintegration, CovarianceMatchesMonteCarlo) {
  const auto readings = RandomReadings(100, 7);
  sensor::ImuModel noise;
  noise.gyro_noise_density = 2e-3;
  noise.accel_noise_density = 2e-2;
  ImuPreintegration clean(sensor::ImuBias(), noise);
  for (const auto& s : readings) clean.Integrate(0.005, s.head<3>(), s.tail<3>());
  const Matrix9d info = clean.Covariance().inverse();
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n01;
  const double sg = noise.gyro_noise_density / std::sqrt(0.005);
  const double sa = noise.accel_noise_density / std::sqrt(0.005);
  const int trials = 2000;
  Matrix9d scatter = Matrix9d::Zero();
  double mahalanobis = 0.0;
  for (int t = 0; t < trials; ++t) {
    ImuPreintegration p(sensor::ImuBias(), noise);
    for (const auto& s : readings) {
      const Eigen::Vector3d ng(n01(rng), n01(rng), n01(rng)), na(n01(rng), n01(rng), n01(rng));
      p.Integrate(0.005, s.head<3>() + sg * ng, s.tail<3>() + sa * na);
    }
    Eigen::Matrix<double, 9, 1> e;
    e << LogSO3<double>(Eigen::Quaterniond(clean.DeltaR().transpose() * p.DeltaR())),
        p.DeltaV() - clean.DeltaV(), p.DeltaP() - clean.DeltaP();
    scatter += e * e.transpose() / trials;
    mahalanobis += e.dot(info * e) / trials;
  }
  EXPECT_NEAR(mahalanobis, 9.0, 0.5);  // chi-square with 9 degrees of freedom, mean 9
  for (int k = 0; k < 9; ++k) {
    EXPECT_NEAR(scatter(k, k) / clean.Covariance()(k, k), 1.0, 0.15) << "state " << k;
  }
}

TEST(ImuPreintegration, RefusesBadInput) {
  sensor::ImuModel bad;
  bad.gyro_noise_density = 0.0;
  EXPECT_THROW(ImuPreintegration(sensor::ImuBias(), bad), std::invalid_argument);
  sensor::ImuBias nan_bias;
  nan_bias.gyro(1) = std::nan("");
  EXPECT_THROW(ImuPreintegration(nan_bias, sensor::ImuModel()), std::invalid_argument);
  ImuPreintegration p{sensor::ImuBias(), sensor::ImuModel()};
  EXPECT_THROW(p.Integrate(0.0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()),
               std::invalid_argument);
  EXPECT_THROW(p.Integrate(0.005, Eigen::Vector3d(std::nan(""), 0, 0), Eigen::Vector3d::Zero()),
               std::invalid_argument);
  EXPECT_EQ(p.NumSamples(), 0);
  EXPECT_THROW(ImuFactor::Create(p, kGravity), std::invalid_argument);
}

TEST(ImuFactor, JacobianChecksPass) {
  verify::JacobianCheckOptions options;
  options.samples = 300;
  const verify::JacobianCheckRun run =
      verify::RunJacobianChecks(verify::ImuFactorJacobianChecks(), "factor.imu.", 1, options);
  EXPECT_TRUE(run.ok()) << run.error;
}

// On the noise-free trajectory the whitened residual at the true states is small against its 15
// degrees of freedom (the Euler discretisation error only).
TEST(ImuFactor, ResidualAtTheTruthIsSmall) {
  const sim::Trajectory traj = TestTrajectory();
  sensor::ImuBias bias;
  const double t0 = 4.0;
  const ImuPreintegration p = Preintegrate(traj, 1000.0, t0, 0.25, bias);
  std::unique_ptr<ceres::CostFunction> f(ImuFactor::Create(p, kGravity));
  double pose_i[7], pose_j[7], v_i[3], v_j[3], b[6] = {0, 0, 0, 0, 0, 0};
  traj.T_w_b(t0).ToParameters(pose_i);
  traj.T_w_b(t0 + 0.25).ToParameters(pose_j);
  for (int k = 0; k < 3; ++k) {
    v_i[k] = traj.velocity_w(t0)(k);
    v_j[k] = traj.velocity_w(t0 + 0.25)(k);
  }
  const double* params[] = {pose_i, v_i, b, pose_j, v_j, b};
  Eigen::Matrix<double, 15, 1> r;
  ASSERT_TRUE(f->Evaluate(params, r.data(), nullptr));
  EXPECT_LT(r.squaredNorm(), 15.0);
}

}  // namespace
}  // namespace plucker
