// On-manifold IMU preintegration between two keyframes i and j (Forster et al., TRO 2017;
// docs/math/imu-preintegration.md).
//
// Body frame b = IMU frame. A reading (gyro w_k, specific force a_k) is taken as constant over a
// step of dt_k seconds and integrated with the rotation at mid-step, with the biases held at the
// linearisation point (b_g, b_a); for phi = (w_k - b_g) dt and R_m = DR Exp(phi / 2):
//   Dp <- Dp + Dv dt + 1/2 R_m (a_k - b_a) dt^2
//   Dv <- Dv + R_m (a_k - b_a) dt
//   DR <- DR Exp(phi)
// The rotation is exact for a constant rate; velocity and position are of second order per
// step. Fed with held samples (the reading at the start of
// each step) the error is O(dt) per unit time; fed with the mean of the readings at both ends of
// the step (PreintegrateSamples below) it is O(dt^2).
//
// Alongside, in the order [dtheta, dv, dp] of the 9-dimensional error state:
// - the covariance, propagated from the continuous-time noise densities (discrete per-sample
//   variance density^2 / dt), jointly with the bias random walk over the window (the bias drift
//   inside a 1 s window is not negligible against the white noise of a MEMS unit: without it
//   the whitened [R, v, p] residual grows from 8.4 to 11.1 for 9 degrees of freedom, test
//   ImuConsistency.IgnoringTheBiasDriftInTheWindowUnderstatesTheUncertainty);
// - the first-order Jacobians of (DR, Dv, Dp) with respect to the biases, so that a small bias
//   change is applied without integrating again:
//   DR(b_g + d) ~ DR Exp(dR_dbg d),  Dv(b + d) ~ Dv + dv_dbg d_g + dv_dba d_a,  same for Dp.
// When the bias moves far from the linearisation point (|d| above a threshold the caller picks),
// Repropagate() integrates the stored samples again at the new bias.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <utility>
#include <vector>

#include "plucker/sensor/imu.h"

namespace plucker {

// Position integration noise (m / sqrt(s)): variance sigma^2 dt added to the position block at
// every step, for the error of the Euler position update (GTSAM's "integration covariance").
// Without it the velocity and position blocks are driven by the same accelerometer noise and the
// covariance of a one-sample preintegration is singular. The default (0.1 mm after 1 s) is far
// below the accelerometer's contribution.
constexpr double kDefaultIntegrationSigma = 1.0e-4;

// Body state in the world w: T_w_b = (R_w_b, p_w), velocity v_w.
struct NavState {
  Eigen::Matrix3d R_w_b = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_w = Eigen::Vector3d::Zero();
};

using Matrix9d = Eigen::Matrix<double, 9, 9>;
using Matrix15d = Eigen::Matrix<double, 15, 15>;

class ImuPreintegration {
 public:
  // Throws std::invalid_argument for noise figures that are not finite and positive or a
  // non-finite bias. (imu.rate_hz is not used: every sample brings its own period.)
  ImuPreintegration(const sensor::ImuBias& bias_lin, const sensor::ImuModel& imu,
                    double integration_sigma = kDefaultIntegrationSigma);

  // Adds one sample held for dt seconds. Throws std::invalid_argument for dt <= 0 or non-finite
  // values (nothing is changed then).
  void Integrate(double dt, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel);

  // Adds a step whose readings were not measured but bridged across an IMU gap (e.g. the mean of
  // the samples at its two ends). Besides the white noise of Integrate, the bridged reading is
  // off by an error that stays constant over the step: per body axis, standard deviations
  // gyro_sigma (rad/s) and accel_sigma (m/s^2), a variance sigma^2 per step instead of the
  // white noise's density^2 / dt (so the velocity's grows as (sigma dt)^2, not density^2 dt).
  // Throws std::invalid_argument as Integrate does, and for sigmas that are not finite and >= 0.
  void IntegrateBridged(double dt, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel,
                        const Eigen::Vector3d& gyro_sigma, const Eigen::Vector3d& accel_sigma);

  // Integrates the stored samples again with a new linearisation point.
  void Repropagate(const sensor::ImuBias& bias_lin);

  double Dt() const { return dt_sum_; }
  int NumSamples() const { return static_cast<int>(samples_.size()); }
  const sensor::ImuBias& BiasLinearisation() const { return bias_lin_; }
  const sensor::ImuModel& Imu() const { return imu_; }
  const Eigen::Matrix3d& DeltaR() const { return delta_R_; }
  const Eigen::Vector3d& DeltaV() const { return delta_v_; }
  const Eigen::Vector3d& DeltaP() const { return delta_p_; }
  // Covariance of the preintegrated [dtheta, dv, dp] given the bias at i.
  Matrix9d Covariance() const { return covariance_.topLeftCorner<9, 9>(); }
  // Joint covariance of [dtheta, dv, dp, b_g(j) - b_g(i), b_a(j) - b_a(i)]: the bias random walk
  // inside the window, and its effect on the deltas, included (as GTSAM's CombinedImuFactor).
  const Matrix15d& JointCovariance() const { return covariance_; }
  const Eigen::Matrix3d& d_R_d_bg() const { return d_R_d_bg_; }
  const Eigen::Matrix3d& d_v_d_bg() const { return d_v_d_bg_; }
  const Eigen::Matrix3d& d_v_d_ba() const { return d_v_d_ba_; }
  const Eigen::Matrix3d& d_p_d_bg() const { return d_p_d_bg_; }
  const Eigen::Matrix3d& d_p_d_ba() const { return d_p_d_ba_; }

  // The deltas corrected to first order for the bias `bias` (instead of the linearisation point).
  Eigen::Matrix3d CorrectedDeltaR(const sensor::ImuBias& bias) const;
  Eigen::Vector3d CorrectedDeltaV(const sensor::ImuBias& bias) const;
  Eigen::Vector3d CorrectedDeltaP(const sensor::ImuBias& bias) const;

  // State at j predicted from the state at i, the bias `bias` and gravity g_w:
  //   R_j = R_i DR,  v_j = v_i + g Dt + R_i Dv,  p_j = p_i + v_i Dt + 1/2 g Dt^2 + R_i Dp.
  NavState Predict(const NavState& state_i, const sensor::ImuBias& bias,
                   const Eigen::Vector3d& gravity_w) const;

 private:
  struct Sample {
    double dt;
    Eigen::Vector3d gyro, accel;
    // Variance of a bridged reading's constant error (IntegrateBridged; zero for a measured one).
    Eigen::Vector3d gyro_var = Eigen::Vector3d::Zero(), accel_var = Eigen::Vector3d::Zero();
  };
  void Reset();
  void Add(const Sample& s);
  void Propagate(const Sample& s);

  sensor::ImuBias bias_lin_;
  sensor::ImuModel imu_;
  double integration_sigma_;
  std::vector<Sample> samples_;
  double dt_sum_ = 0.0;
  Eigen::Matrix3d delta_R_;
  Eigen::Vector3d delta_v_, delta_p_;
  Matrix15d covariance_;
  Eigen::Matrix3d d_R_d_bg_, d_v_d_bg_, d_v_d_ba_, d_p_d_bg_, d_p_d_ba_;
};

// Preintegration of a sample stream over [t0, t1]: readings are interpolated linearly between
// samples, and each sub-interval between consecutive sample times (cut at t0 and t1) integrates
// the mean of the readings at its two ends. With the mid-step rotation of Integrate the scheme is
// of second order (test ImuPreintegration.SampleStreamConvergesAtSecondOrder). Throws
// std::invalid_argument when t1 <= t0 or the samples (increasing times) do not cover [t0, t1].
//
// gap_s: a step between samples longer than this is a gap, bridged (IntegrateBridged) with the
// readings' own spread about their mean over the gap_window samples on either side of it (at rest
// that is the rotor vibration, which the interpolated readings miss: the mean of two vibrating
// end samples is off the gap's true mean by about that spread). Infinity: no gap handling.
ImuPreintegration PreintegrateSamples(const std::vector<sensor::ImuSample>& imu, double t0,
                                      double t1, const sensor::ImuBias& bias,
                                      const sensor::ImuModel& model,
                                      double gap_s = std::numeric_limits<double>::infinity());

// The spread (standard deviation per axis) of the gyro and accelerometer readings about their
// mean over up to `count` samples on either side of the step from sample k to k + 1.
std::pair<Eigen::Vector3d, Eigen::Vector3d> ReadingSpreadAround(
    const std::vector<sensor::ImuSample>& imu, std::size_t k, int count);

}  // namespace plucker
