#include "plucker/inertial/static_initializer.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "plucker/inertial/gravity.h"

namespace plucker {
namespace inertial {
namespace {

struct Moments {
  int n = 0;
  Eigen::Vector3d gyro_mean = Eigen::Vector3d::Zero(), accel_mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d gyro_cov = Eigen::Matrix3d::Zero(), accel_cov = Eigen::Matrix3d::Zero();
};

// Means and (population) covariances of the readings with indices [begin, end).
Moments ComputeMoments(const std::vector<sensor::ImuSample>& imu, std::size_t begin,
                       std::size_t end) {
  Moments m;
  m.n = static_cast<int>(end - begin);
  if (m.n == 0) return m;
  for (std::size_t k = begin; k < end; ++k) {
    m.gyro_mean += imu[k].gyro;
    m.accel_mean += imu[k].accel;
  }
  m.gyro_mean /= m.n;
  m.accel_mean /= m.n;
  for (std::size_t k = begin; k < end; ++k) {
    const Eigen::Vector3d dg = imu[k].gyro - m.gyro_mean, da = imu[k].accel - m.accel_mean;
    m.gyro_cov += dg * dg.transpose();
    m.accel_cov += da * da.transpose();
  }
  m.gyro_cov /= m.n;
  m.accel_cov /= m.n;
  return m;
}

void Validate(const std::vector<sensor::ImuSample>& imu, const StaticInitOptions& o) {
  const bool options_ok = o.block_seconds > 0 && o.max_accel_std > 0 && o.max_gyro_std > 0 &&
                          o.min_still_seconds >= 0 && o.gravity_magnitude > 0 &&
                          o.max_gravity_deviation > 0 && o.accel_bias_prior_sigma >= 0 &&
                          o.accel_bias_prior.allFinite();
  if (!options_ok) throw std::invalid_argument("InitializeStatic: invalid options");
  for (std::size_t k = 0; k < imu.size(); ++k) {
    if (!std::isfinite(imu[k].t) || !imu[k].gyro.allFinite() || !imu[k].accel.allFinite()) {
      throw std::invalid_argument("InitializeStatic: non-finite IMU sample " + std::to_string(k));
    }
    if (k > 0 && imu[k].t <= imu[k - 1].t) {
      throw std::invalid_argument("InitializeStatic: IMU timestamps do not increase at sample " +
                                  std::to_string(k));
    }
  }
}

bool MovingFrameIn(const std::vector<ImageMotionFlag>& flags, double t0, double t1) {
  for (const ImageMotionFlag& f : flags) {
    if (!f.still && f.t >= t0 && f.t < t1) return true;
  }
  return false;
}

std::string Format(const char* fmt, double a, double b) {
  char buf[256];
  std::snprintf(buf, sizeof(buf), fmt, a, b);
  return buf;
}

// Fills the estimates of `r` from the moments of the still span (docs: "Static initialisation").
void Estimate(const Moments& m, const StaticInitOptions& o, StaticInitResult* r) {
  // The horizontal part of the bias prior is removed before normalising; it depends on the up
  // direction, so two passes (the second changes it by O(|b_prior|^2 / |g|)).
  Eigen::Vector3d u = m.accel_mean.normalized();
  Eigen::Vector3d a_c = m.accel_mean;
  Eigen::Matrix3d P = Eigen::Matrix3d::Identity();
  for (int pass = 0; pass < 2; ++pass) {
    P = Eigen::Matrix3d::Identity() - u * u.transpose();
    a_c = m.accel_mean - P * o.accel_bias_prior;
    u = a_c.normalized();
  }
  P = Eigen::Matrix3d::Identity() - u * u.transpose();
  const double n = m.n;
  const Eigen::Matrix3d cov_accel_mean = m.accel_cov / n;
  const double sigma2 = o.accel_bias_prior_sigma * o.accel_bias_prior_sigma;

  r->up_b = u;
  r->R_w_b = GravityAlignedRotation(u);
  r->gravity_b = -o.gravity_magnitude * u;
  r->up_covariance = P * (cov_accel_mean + sigma2 * Eigen::Matrix3d::Identity()) * P.transpose() /
                     a_c.squaredNorm();
  r->tilt_sigma = std::sqrt(std::max(
      0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(r->up_covariance, Eigen::EigenvaluesOnly)
               .eigenvalues()
               .maxCoeff()));
  r->bias.gyro = m.gyro_mean;
  r->bias.accel = P * o.accel_bias_prior + (a_c.norm() - o.gravity_magnitude) * u;
  r->gyro_bias_covariance = m.gyro_cov / n;
  r->accel_bias_covariance = u * u.transpose() * u.dot(cov_accel_mean * u) + sigma2 * P;
  r->gyro_std = m.gyro_cov.diagonal().cwiseSqrt();
  r->accel_std = m.accel_cov.diagonal().cwiseSqrt();
  r->accel_norm_mean = a_c.norm();
}

}  // namespace

const char* ToString(StaticInitStatus status) {
  switch (status) {
    case StaticInitStatus::kSuccess:
      return "success";
    case StaticInitStatus::kNotStill:
      return "not still";
    case StaticInitStatus::kGravityMismatch:
      return "gravity mismatch";
    case StaticInitStatus::kTooFewSamples:
      return "too few samples";
  }
  return "unknown";
}

StaticInitResult InitializeStatic(const std::vector<sensor::ImuSample>& imu,
                                  const StaticInitOptions& o, double t_begin,
                                  const std::vector<ImageMotionFlag>& image_flags) {
  Validate(imu, o);
  StaticInitResult r;
  std::size_t first = 0;
  while (first < imu.size() && imu[first].t < t_begin) ++first;
  if (first == imu.size() || imu.back().t - imu[first].t < o.block_seconds) {
    r.status = StaticInitStatus::kTooFewSamples;
    r.message = "the IMU log does not cover one block of the still test";
    return r;
  }
  // Blocks [t0 + b B, t0 + (b + 1) B) while the log covers them and they stay still.
  const double t0 = imu[first].t;
  std::size_t k = first;
  bool motion_found = false;
  while (true) {
    const double begin = t0 + r.blocks_still * o.block_seconds;
    const double end = begin + o.block_seconds;
    if (imu.back().t < end) break;  // the log ends inside this block
    std::size_t k_end = k;
    while (k_end < imu.size() && imu[k_end].t < end) ++k_end;
    const Moments m = ComputeMoments(imu, k, k_end);
    const double accel_spread = std::sqrt(m.accel_cov.trace());
    const double gyro_spread = std::sqrt(m.gyro_cov.trace());
    if (m.n < 2 || accel_spread > o.max_accel_std || gyro_spread > o.max_gyro_std ||
        MovingFrameIn(image_flags, begin, end)) {
      motion_found = true;
      r.first_moving_block_accel_std = accel_spread;
      break;
    }
    ++r.blocks_still;
    k = k_end;
  }
  // The block before the motion may hold its onset: drop it.
  const int blocks_used = motion_found ? std::max(0, r.blocks_still - 1) : r.blocks_still;
  r.still_begin = t0;
  r.still_end = t0 + blocks_used * o.block_seconds;
  if (blocks_used * o.block_seconds < o.min_still_seconds || blocks_used == 0) {
    r.status = StaticInitStatus::kNotStill;
    r.message = Format("still for %.2f s from the start, %.2f s are needed", r.still_end - t0,
                       o.min_still_seconds);
    return r;
  }
  std::size_t end = first;
  while (end < imu.size() && imu[end].t < r.still_end) ++end;
  const Moments m = ComputeMoments(imu, first, end);
  r.samples_used = m.n;
  Estimate(m, o, &r);
  if (std::abs(r.accel_norm_mean - o.gravity_magnitude) > o.max_gravity_deviation) {
    r.status = StaticInitStatus::kGravityMismatch;
    r.message = Format("the mean specific force is %.3f m/s^2, |g| is %.3f m/s^2",
                       r.accel_norm_mean, o.gravity_magnitude);
    return r;
  }
  r.status = StaticInitStatus::kSuccess;
  return r;
}

}  // namespace inertial
}  // namespace plucker
