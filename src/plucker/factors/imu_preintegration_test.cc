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

// Scatter and mean Mahalanobis distance (against clean's covariance) of `trials` noisy
// preintegrations, each made by noisy(&p) from a fresh ImuPreintegration with clean's model.
struct MonteCarlo {
  Matrix9d scatter = Matrix9d::Zero();
  double mahalanobis = 0.0;
};

template <typename Noisy>
MonteCarlo MonteCarloAgainst(const ImuPreintegration& clean, int trials, Noisy noisy) {
  const Matrix9d info = clean.Covariance().inverse();
  MonteCarlo mc;
  for (int t = 0; t < trials; ++t) {
    ImuPreintegration p(sensor::ImuBias(), clean.Imu());
    noisy(&p);
    Eigen::Matrix<double, 9, 1> e;
    e << LogSO3<double>(Eigen::Quaterniond(clean.DeltaR().transpose() * p.DeltaR())),
        p.DeltaV() - clean.DeltaV(), p.DeltaP() - clean.DeltaP();
    mc.scatter += e * e.transpose() / trials;
    mc.mahalanobis += e.dot(info * e) / trials;
  }
  return mc;
}

// The propagated covariance against the scatter of 2000 noisy integrations of the same motion.
TEST(ImuPreintegration, CovarianceMatchesMonteCarlo) {
  const auto readings = RandomReadings(100, 7);
  sensor::ImuModel noise;
  noise.gyro_noise_density = 2e-3;
  noise.accel_noise_density = 2e-2;
  ImuPreintegration clean(sensor::ImuBias(), noise);
  for (const auto& s : readings) clean.Integrate(0.005, s.head<3>(), s.tail<3>());
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n01;
  const double sg = noise.gyro_noise_density / std::sqrt(0.005);
  const double sa = noise.accel_noise_density / std::sqrt(0.005);
  const auto [scatter, mahalanobis] = MonteCarloAgainst(clean, 2000, [&](ImuPreintegration* p) {
    for (const auto& s : readings) {
      const Eigen::Vector3d ng(n01(rng), n01(rng), n01(rng)), na(n01(rng), n01(rng), n01(rng));
      p->Integrate(0.005, s.head<3>() + sg * ng, s.tail<3>() + sa * na);
    }
  });
  EXPECT_NEAR(mahalanobis, 9.0, 0.5);  // chi-square with 9 degrees of freedom, mean 9
  for (int k = 0; k < 9; ++k) {
    EXPECT_NEAR(scatter(k, k) / clean.Covariance()(k, k), 1.0, 0.15) << "state " << k;
  }
}

// A bridged step (IntegrateBridged: an IMU gap of 0.2 s whose reading is off by an error constant
// over the step) in the middle of measured samples: the covariance against Monte Carlo draws of
// that error and of the white noise of the measured samples. Treated as white noise instead, the
// same error would be understated 40x in variance (density^2 / dt against sigma^2 per step).
TEST(ImuPreintegration, BridgedStepCovarianceMatchesMonteCarlo) {
  const auto readings = RandomReadings(41, 8);
  sensor::ImuModel noise;
  noise.gyro_noise_density = 2e-3;
  noise.accel_noise_density = 2e-2;
  const Eigen::Vector3d gyro_sigma(0.02, 0.01, 0.03), accel_sigma(0.3, 1.0, 0.2);
  const int gap = 20;  // the step of sample 20 lasts 0.2 s
  const double gap_dt = 0.2;
  auto step = [&](ImuPreintegration* p, int k, const Eigen::Vector3d& g, const Eigen::Vector3d& a) {
    if (k == gap)
      p->IntegrateBridged(gap_dt, g, a, gyro_sigma, accel_sigma);
    else
      p->Integrate(0.005, g, a);
  };
  ImuPreintegration clean(sensor::ImuBias(), noise);
  for (int k = 0; k < 41; ++k) step(&clean, k, readings[k].head<3>(), readings[k].tail<3>());
  std::mt19937_64 rng(12);
  std::normal_distribution<double> n01;
  const double sg = noise.gyro_noise_density / std::sqrt(0.005);
  const double sa = noise.accel_noise_density / std::sqrt(0.005);
  const auto [scatter, mahalanobis] = MonteCarloAgainst(clean, 2000, [&](ImuPreintegration* p) {
    for (int k = 0; k < 41; ++k) {
      const Eigen::Vector3d ng(n01(rng), n01(rng), n01(rng)), na(n01(rng), n01(rng), n01(rng));
      Eigen::Vector3d eg = sg * ng, ea = sa * na;
      if (k == gap) {  // the bridged step: white noise over 0.2 s plus the constant error
        eg = eg * std::sqrt(0.005 / gap_dt) +
             gyro_sigma.cwiseProduct(Eigen::Vector3d(n01(rng), n01(rng), n01(rng)));
        ea = ea * std::sqrt(0.005 / gap_dt) +
             accel_sigma.cwiseProduct(Eigen::Vector3d(n01(rng), n01(rng), n01(rng)));
      }
      step(p, k, readings[k].head<3>() + eg, readings[k].tail<3>() + ea);
    }
  });
  EXPECT_NEAR(mahalanobis, 9.0, 0.6);
  for (int k = 0; k < 9; ++k) {
    EXPECT_NEAR(scatter(k, k) / clean.Covariance()(k, k), 1.0, 0.15) << "state " << k;
  }
  // Without the bridged error the velocity block is far too small for that scatter.
  ImuPreintegration white(sensor::ImuBias(), noise);
  for (int k = 0; k < 41; ++k) {
    const double dt = k == gap ? gap_dt : 0.005;
    white.Integrate(dt, readings[k].head<3>(), readings[k].tail<3>());
  }
  EXPECT_GT(scatter(4, 4) / white.Covariance()(4, 4), 10.0);
}

// PreintegrateSamples with gap_s: a step longer than gap_s between samples is bridged with the
// readings' spread around it (its 20 samples on either side); the same deltas, a larger
// covariance; without a gap, or with gap_s infinite, the same preintegration as before.
TEST(ImuPreintegration, SampleStreamBridgesAGap) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n01;
  std::vector<sensor::ImuSample> imu;
  for (int k = 0; k <= 200; ++k) {
    if (k > 90 && k < 130) continue;  // no samples from 0.455 to 0.645 s: a 0.2 s step
    sensor::ImuSample s;
    s.t = 0.005 * k;
    s.gyro = Eigen::Vector3d::Zero();  // no rotation: the velocity's covariance is exact
    s.accel = Eigen::Vector3d(0.0, 0.0, 9.81) + Eigen::Vector3d(0.0, 1.0 * n01(rng), 0.0);
    imu.push_back(s);
  }
  const sensor::ImuModel model;
  const sensor::ImuBias bias;
  const ImuPreintegration plain = PreintegrateSamples(imu, 0.1, 0.9, bias, model);
  const ImuPreintegration bridged = PreintegrateSamples(imu, 0.1, 0.9, bias, model, 0.05);
  EXPECT_EQ(bridged.NumSamples(), plain.NumSamples());
  EXPECT_LT((bridged.DeltaV() - plain.DeltaV()).norm(), 1e-12);
  EXPECT_LT((bridged.DeltaP() - plain.DeltaP()).norm(), 1e-12);
  // The y velocity: the bridged error (about 1 m/s^2 over 0.2 s) in quadrature with the noise.
  const auto [gyro_sigma, accel_sigma] = ReadingSpreadAround(imu, 90, 20);
  EXPECT_NEAR(accel_sigma.y(), 1.0, 0.3);
  EXPECT_LT(accel_sigma.x(), 1e-9);
  EXPECT_LT(gyro_sigma.norm(), 1e-12);
  const double bridged_var = accel_sigma.y() * accel_sigma.y() * 0.2 * 0.2;
  EXPECT_NEAR(bridged.Covariance()(4, 4) - plain.Covariance()(4, 4), bridged_var,
              0.05 * bridged_var);
  EXPECT_NEAR(bridged.Covariance()(3, 3), plain.Covariance()(3, 3), 1e-15);  // x: no spread
  // Away from the gap (and no longer step than gap_s): bit-identical.
  const ImuPreintegration before = PreintegrateSamples(imu, 0.1, 0.4, bias, model);
  const ImuPreintegration before_gap = PreintegrateSamples(imu, 0.1, 0.4, bias, model, 0.05);
  EXPECT_EQ(before.Covariance(), before_gap.Covariance());
  EXPECT_EQ(before.DeltaV(), before_gap.DeltaV());
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
  const Eigen::Vector3d z = Eigen::Vector3d::Zero();
  EXPECT_THROW(p.IntegrateBridged(0.1, z, z, Eigen::Vector3d(-1, 0, 0), z), std::invalid_argument);
  EXPECT_THROW(p.IntegrateBridged(0.1, z, z, z, Eigen::Vector3d(std::nan(""), 0, 0)),
               std::invalid_argument);
  EXPECT_THROW(p.IntegrateBridged(-0.1, z, z, z, z), std::invalid_argument);
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
