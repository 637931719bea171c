#include "plucker/factors/imu_preintegration.h"

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

ImuPreintegration::ImuPreintegration(const ImuBias& bias_lin, const sensor::ImuModel& imu,
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
  if (!FinitePositive(dt)) {
    throw std::invalid_argument("ImuPreintegration: sample period must be finite and positive");
  }
  if (!gyro.allFinite() || !accel.allFinite()) {
    throw std::invalid_argument("ImuPreintegration: non-finite IMU sample");
  }
  samples_.push_back({dt, gyro, accel});
  Propagate(samples_.back());
}

void ImuPreintegration::Repropagate(const ImuBias& bias_lin) {
  if (!bias_lin.gyro.allFinite() || !bias_lin.accel.allFinite()) {
    throw std::invalid_argument("ImuPreintegration: non-finite bias");
  }
  bias_lin_ = bias_lin;
  Reset();
  for (const Sample& s : samples_) Propagate(s);
}

// One Euler step; every right-hand side uses the values before the step (docs/math).
void ImuPreintegration::Propagate(const Sample& s) {
  const double dt = s.dt, dt2 = dt * dt;
  const Eigen::Vector3d a = s.accel - bias_lin_.accel;
  const Eigen::Vector3d phi = (s.gyro - bias_lin_.gyro) * dt;
  const Eigen::Matrix3d dR = ExpSO3Matrix<double>(phi);
  const Eigen::Matrix3d Jr = RightJacobianSO3(phi);
  const Eigen::Matrix3d R = delta_R_;
  const Eigen::Matrix3d R_a_hat = R * Hat<double>(a);

  // Covariance: Sigma <- A Sigma A^T + B_g Q_g B_g^T + B_a Q_a B_a^T on [dtheta, dv, dp].
  Matrix9d A = Matrix9d::Identity();
  A.block<3, 3>(0, 0) = dR.transpose();
  A.block<3, 3>(3, 0) = -R_a_hat * dt;
  A.block<3, 3>(6, 0) = -0.5 * R_a_hat * dt2;
  A.block<3, 3>(6, 3) = Eigen::Matrix3d::Identity() * dt;
  Eigen::Matrix<double, 9, 3> B_g = Eigen::Matrix<double, 9, 3>::Zero();
  Eigen::Matrix<double, 9, 3> B_a = Eigen::Matrix<double, 9, 3>::Zero();
  B_g.block<3, 3>(0, 0) = Jr * dt;
  B_a.block<3, 3>(3, 0) = R * dt;
  B_a.block<3, 3>(6, 0) = 0.5 * R * dt2;
  const double var_g = imu_.gyro_noise_density * imu_.gyro_noise_density / dt;
  const double var_a = imu_.accel_noise_density * imu_.accel_noise_density / dt;
  covariance_ = A * covariance_ * A.transpose() + var_g * B_g * B_g.transpose() +
                var_a * B_a * B_a.transpose();
  covariance_.block<3, 3>(6, 6).diagonal().array() += integration_sigma_ * integration_sigma_ * dt;

  // Bias Jacobians (position first: it reads the velocity and rotation Jacobians before the step).
  d_p_d_ba_ += d_v_d_ba_ * dt - 0.5 * R * dt2;
  d_p_d_bg_ += d_v_d_bg_ * dt - 0.5 * R_a_hat * d_R_d_bg_ * dt2;
  d_v_d_ba_ -= R * dt;
  d_v_d_bg_ -= R_a_hat * d_R_d_bg_ * dt;
  d_R_d_bg_ = dR.transpose() * d_R_d_bg_ - Jr * dt;

  // The deltas.
  delta_p_ += delta_v_ * dt + 0.5 * R * a * dt2;
  delta_v_ += R * a * dt;
  delta_R_ = R * dR;
  dt_sum_ += dt;
}

Eigen::Matrix3d ImuPreintegration::CorrectedDeltaR(const ImuBias& bias) const {
  return delta_R_ * ExpSO3Matrix<double>(d_R_d_bg_ * (bias.gyro - bias_lin_.gyro));
}

Eigen::Vector3d ImuPreintegration::CorrectedDeltaV(const ImuBias& bias) const {
  return delta_v_ + d_v_d_bg_ * (bias.gyro - bias_lin_.gyro) +
         d_v_d_ba_ * (bias.accel - bias_lin_.accel);
}

Eigen::Vector3d ImuPreintegration::CorrectedDeltaP(const ImuBias& bias) const {
  return delta_p_ + d_p_d_bg_ * (bias.gyro - bias_lin_.gyro) +
         d_p_d_ba_ * (bias.accel - bias_lin_.accel);
}

NavState ImuPreintegration::Predict(const NavState& i, const ImuBias& bias,
                                    const Eigen::Vector3d& gravity_w) const {
  const double T = dt_sum_;
  NavState j;
  j.R_w_b = i.R_w_b * CorrectedDeltaR(bias);
  j.v_w = i.v_w + gravity_w * T + i.R_w_b * CorrectedDeltaV(bias);
  j.p_w = i.p_w + i.v_w * T + 0.5 * gravity_w * T * T + i.R_w_b * CorrectedDeltaP(bias);
  return j;
}

}  // namespace plucker
