#include "plucker/factors/imu_preintegration.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "plucker/geometry/so3.h"

namespace plucker {

namespace {

bool FinitePositive(double x) { return std::isfinite(x) && x > 0.0; }

bool ValidNoise(const sensor::ImuModel& imu, double integration_sigma) {
  return FinitePositive(imu.gyro_noise_density) && FinitePositive(imu.accel_noise_density) &&
         FinitePositive(imu.gyro_bias_random_walk) && FinitePositive(imu.accel_bias_random_walk) &&
         FinitePositive(integration_sigma);
}

}  // namespace

ImuPreintegration::ImuPreintegration(const sensor::ImuBias& bias_lin, const sensor::ImuModel& imu,
                                     double integration_sigma)
    : bias_lin_(bias_lin), imu_(imu), integration_sigma_(integration_sigma) {
  if (!ValidNoise(imu, integration_sigma)) {
    throw std::invalid_argument(
        "ImuPreintegration: noise densities and random walks must be finite and positive");
  }
  if (!bias_lin.gyro.allFinite() || !bias_lin.accel.allFinite()) {
    throw std::invalid_argument("ImuPreintegration: non-finite bias");
  }
  Reset();
}

void ImuPreintegration::Reset() {
  dt_sum_ = 0.0;
  delta_R_.setIdentity();
  delta_v_.setZero();
  delta_p_.setZero();
  covariance_.setZero();
  d_R_d_bg_.setZero();
  d_v_d_bg_.setZero();
  d_v_d_ba_.setZero();
  d_p_d_bg_.setZero();
  d_p_d_ba_.setZero();
}

void ImuPreintegration::Integrate(double dt, const Eigen::Vector3d& gyro,
                                  const Eigen::Vector3d& accel) {
  Add({dt, gyro, accel});
}

void ImuPreintegration::IntegrateBridged(double dt, const Eigen::Vector3d& gyro,
                                         const Eigen::Vector3d& accel,
                                         const Eigen::Vector3d& gyro_sigma,
                                         const Eigen::Vector3d& accel_sigma) {
  if (!gyro_sigma.allFinite() || !accel_sigma.allFinite() || gyro_sigma.minCoeff() < 0.0 ||
      accel_sigma.minCoeff() < 0.0) {
    throw std::invalid_argument("ImuPreintegration: bridged reading sigmas must be finite, >= 0");
  }
  Add({dt, gyro, accel, gyro_sigma.cwiseAbs2(), accel_sigma.cwiseAbs2()});
}

void ImuPreintegration::Add(const Sample& s) {
  if (!FinitePositive(s.dt)) {
    throw std::invalid_argument("ImuPreintegration: sample period must be finite and positive");
  }
  if (!s.gyro.allFinite() || !s.accel.allFinite()) {
    throw std::invalid_argument("ImuPreintegration: non-finite IMU sample");
  }
  samples_.push_back(s);
  Propagate(samples_.back());
}

void ImuPreintegration::Repropagate(const sensor::ImuBias& bias_lin) {
  if (!bias_lin.gyro.allFinite() || !bias_lin.accel.allFinite()) {
    throw std::invalid_argument("ImuPreintegration: non-finite bias");
  }
  bias_lin_ = bias_lin;
  Reset();
  for (const Sample& s : samples_) Propagate(s);
}

// One step with the rotation at mid-step, R_m = DR Exp(phi / 2) (docs/math/imu-preintegration.md);
// every right-hand side uses the values before the step.
void ImuPreintegration::Propagate(const Sample& s) {
  const double dt = s.dt, dt2 = dt * dt;
  const Eigen::Vector3d a = s.accel - bias_lin_.accel;
  const Eigen::Vector3d phi = (s.gyro - bias_lin_.gyro) * dt;
  const Eigen::Matrix3d dR = ExpSO3Matrix<double>(phi);
  const Eigen::Matrix3d Jr = RightJacobianSO3(phi);
  const Eigen::Matrix3d half_T = ExpSO3Matrix<double>(0.5 * phi).transpose();
  const Eigen::Matrix3d Jr_half = RightJacobianSO3(0.5 * phi);
  const Eigen::Matrix3d R_m = delta_R_ * half_T.transpose();
  const Eigen::Matrix3d R_m_a_hat = R_m * Hat<double>(a);

  // Covariance of [dtheta, dv, dp]: Sigma <- A Sigma A^T + B_g Q_g B_g^T + B_a Q_a B_a^T.
  Matrix9d A = Matrix9d::Identity();
  A.block<3, 3>(0, 0) = dR.transpose();
  A.block<3, 3>(3, 0) = -R_m_a_hat * half_T * dt;
  A.block<3, 3>(6, 0) = -0.5 * R_m_a_hat * half_T * dt2;
  A.block<3, 3>(6, 3) = Eigen::Matrix3d::Identity() * dt;
  Eigen::Matrix<double, 9, 3> B_g = Eigen::Matrix<double, 9, 3>::Zero(), B_a = B_g;
  B_g.block<3, 3>(0, 0) = Jr * dt;
  B_g.block<3, 3>(3, 0) = -0.5 * R_m_a_hat * Jr_half * dt2;
  B_g.block<3, 3>(6, 0) = -0.25 * R_m_a_hat * Jr_half * dt2 * dt;
  B_a.block<3, 3>(3, 0) = R_m * dt;
  B_a.block<3, 3>(6, 0) = 0.5 * R_m * dt2;
  const double var_g = imu_.gyro_noise_density * imu_.gyro_noise_density / dt;
  const double var_a = imu_.accel_noise_density * imu_.accel_noise_density / dt;
  // Joint with the bias drift beta since i: the reading is corrected by b_i, so beta enters the
  // step as the noise does, with the opposite sign.
  Matrix15d A15 = Matrix15d::Identity();
  A15.topLeftCorner<9, 9>() = A;
  A15.block<9, 3>(0, 9) = -B_g;
  A15.block<9, 3>(0, 12) = -B_a;
  covariance_ = A15 * covariance_ * A15.transpose();
  covariance_.topLeftCorner<9, 9>() +=
      var_g * B_g * B_g.transpose() + var_a * B_a * B_a.transpose();
  if (!s.gyro_var.isZero() || !s.accel_var.isZero()) {  // a bridged step's constant error
    covariance_.topLeftCorner<9, 9>() += B_g * s.gyro_var.asDiagonal() * B_g.transpose() +
                                         B_a * s.accel_var.asDiagonal() * B_a.transpose();
  }
  covariance_.block<3, 3>(6, 6).diagonal().array() += integration_sigma_ * integration_sigma_ * dt;
  covariance_.block<3, 3>(9, 9).diagonal().array() +=
      imu_.gyro_bias_random_walk * imu_.gyro_bias_random_walk * dt;
  covariance_.block<3, 3>(12, 12).diagonal().array() +=
      imu_.accel_bias_random_walk * imu_.accel_bias_random_walk * dt;

  // Bias Jacobians (position first: it reads the velocity Jacobians before the step).
  const Eigen::Matrix3d d_Rm_d_bg = half_T * d_R_d_bg_ - 0.5 * Jr_half * dt;
  d_p_d_ba_ += d_v_d_ba_ * dt - 0.5 * R_m * dt2;
  d_p_d_bg_ += d_v_d_bg_ * dt - 0.5 * R_m_a_hat * d_Rm_d_bg * dt2;
  d_v_d_ba_ -= R_m * dt;
  d_v_d_bg_ -= R_m_a_hat * d_Rm_d_bg * dt;
  d_R_d_bg_ = dR.transpose() * d_R_d_bg_ - Jr * dt;

  // The deltas.
  delta_p_ += delta_v_ * dt + 0.5 * R_m * a * dt2;
  delta_v_ += R_m * a * dt;
  delta_R_ = delta_R_ * dR;
  dt_sum_ += dt;
}

Eigen::Matrix3d ImuPreintegration::CorrectedDeltaR(const sensor::ImuBias& bias) const {
  return delta_R_ * ExpSO3Matrix<double>(d_R_d_bg_ * (bias.gyro - bias_lin_.gyro));
}

Eigen::Vector3d ImuPreintegration::CorrectedDeltaV(const sensor::ImuBias& bias) const {
  return delta_v_ + d_v_d_bg_ * (bias.gyro - bias_lin_.gyro) +
         d_v_d_ba_ * (bias.accel - bias_lin_.accel);
}

Eigen::Vector3d ImuPreintegration::CorrectedDeltaP(const sensor::ImuBias& bias) const {
  return delta_p_ + d_p_d_bg_ * (bias.gyro - bias_lin_.gyro) +
         d_p_d_ba_ * (bias.accel - bias_lin_.accel);
}

NavState ImuPreintegration::Predict(const NavState& i, const sensor::ImuBias& bias,
                                    const Eigen::Vector3d& gravity_w) const {
  const double T = dt_sum_;
  NavState j;
  j.R_w_b = i.R_w_b * CorrectedDeltaR(bias);
  j.v_w = i.v_w + gravity_w * T + i.R_w_b * CorrectedDeltaV(bias);
  j.p_w = i.p_w + i.v_w * T + 0.5 * gravity_w * T * T + i.R_w_b * CorrectedDeltaP(bias);
  return j;
}

namespace {

// The samples on either side of a gap whose spread sets its bridged readings' error (0.1 s at
// EuRoC's 200 Hz).
constexpr int kGapSpreadSamples = 20;

// The readings at time t, interpolated linearly between samples k and k + 1.
std::pair<Eigen::Vector3d, Eigen::Vector3d> ReadingAt(const std::vector<sensor::ImuSample>& imu,
                                                      std::size_t k, double t) {
  const sensor::ImuSample &a = imu[k], &b = imu[k + 1];
  const double u = std::clamp((t - a.t) / (b.t - a.t), 0.0, 1.0);
  return {a.gyro + u * (b.gyro - a.gyro), a.accel + u * (b.accel - a.accel)};
}

}  // namespace

std::pair<Eigen::Vector3d, Eigen::Vector3d> ReadingSpreadAround(
    const std::vector<sensor::ImuSample>& imu, std::size_t k, int count) {
  const std::size_t n = static_cast<std::size_t>(std::max(count, 1));
  const std::size_t first = k + 1 > n ? k + 1 - n : 0;
  const std::size_t last = std::min(imu.size(), k + 1 + n);  // one past
  Eigen::Vector3d mean_g = Eigen::Vector3d::Zero(), mean_a = mean_g;
  for (std::size_t i = first; i < last; ++i) {
    mean_g += imu[i].gyro;
    mean_a += imu[i].accel;
  }
  const double m = static_cast<double>(last - first);
  mean_g /= m;
  mean_a /= m;
  Eigen::Vector3d var_g = Eigen::Vector3d::Zero(), var_a = var_g;
  for (std::size_t i = first; i < last; ++i) {
    var_g += (imu[i].gyro - mean_g).cwiseAbs2();
    var_a += (imu[i].accel - mean_a).cwiseAbs2();
  }
  return {(var_g / m).cwiseSqrt(), (var_a / m).cwiseSqrt()};
}

ImuPreintegration PreintegrateSamples(const std::vector<sensor::ImuSample>& imu, double t0,
                                      double t1, const sensor::ImuBias& bias,
                                      const sensor::ImuModel& model, double gap_s) {
  if (!(t1 > t0) || imu.size() < 2 || t0 < imu.front().t || t1 > imu.back().t) {
    throw std::invalid_argument("PreintegrateSamples: the samples do not cover the interval");
  }
  ImuPreintegration p(bias, model);
  // The last sample at or before t0.
  std::size_t k = static_cast<std::size_t>(
      std::upper_bound(imu.begin(), imu.end(), t0,
                       [](double t, const sensor::ImuSample& s) { return t < s.t; }) -
      imu.begin() - 1);
  for (; k + 1 < imu.size() && imu[k].t < t1; ++k) {
    const double a = std::max(imu[k].t, t0), b = std::min(imu[k + 1].t, t1);
    if (!(b > a)) continue;
    const auto [gyro_a, accel_a] = ReadingAt(imu, k, a);
    const auto [gyro_b, accel_b] = ReadingAt(imu, k, b);
    if (imu[k + 1].t - imu[k].t > gap_s) {
      const auto [gyro_sigma, accel_sigma] = ReadingSpreadAround(imu, k, kGapSpreadSamples);
      p.IntegrateBridged(b - a, 0.5 * (gyro_a + gyro_b), 0.5 * (accel_a + accel_b), gyro_sigma,
                         accel_sigma);
    } else {
      p.Integrate(b - a, 0.5 * (gyro_a + gyro_b), 0.5 * (accel_a + accel_b));
    }
  }
  return p;
}

}  // namespace plucker
