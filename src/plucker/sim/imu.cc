#include "plucker/sim/imu.h"

#include <cmath>
#include <random>
#include <stdexcept>

namespace plucker {
namespace sim {

namespace {

void CheckDensity(double v, const char* name) {
  if (!std::isfinite(v) || v < 0.0) {
    throw std::invalid_argument(std::string("SimulateImu: invalid ") + name);
  }
}

}  // namespace

std::vector<sensor::ImuSample> SimulateImu(const Trajectory& trajectory, const ImuOptions& options,
                                           std::uint64_t seed) {
  if (!std::isfinite(options.model.rate_hz) || options.model.rate_hz <= 0.0) {
    throw std::invalid_argument("SimulateImu: rate_hz must be finite and positive");
  }
  CheckDensity(options.model.gyro_noise_density, "gyro_noise_density");
  CheckDensity(options.model.accel_noise_density, "accel_noise_density");
  CheckDensity(options.model.gyro_bias_random_walk, "gyro_bias_random_walk");
  CheckDensity(options.model.accel_bias_random_walk, "accel_bias_random_walk");
  if (!options.initial_gyro_bias.allFinite() || !options.initial_accel_bias.allFinite() ||
      !options.gravity_w.allFinite()) {
    throw std::invalid_argument("SimulateImu: non-finite bias or gravity");
  }
  const double duration = trajectory.duration();
  if (!std::isfinite(duration) || duration < 0.0) {
    throw std::invalid_argument("SimulateImu: invalid trajectory duration");
  }
  const double dt = 1.0 / options.model.rate_hz;
  const double count = std::ceil(duration * options.model.rate_hz - 1e-9);
  if (count > 1e8) throw std::invalid_argument("SimulateImu: more than 1e8 samples");
  const int n = static_cast<int>(count) + 1;

  // Discrete standard deviations from the continuous densities.
  const double sigma_g = options.model.gyro_noise_density / std::sqrt(dt);
  const double sigma_a = options.model.accel_noise_density / std::sqrt(dt);
  const double sigma_bg = options.model.gyro_bias_random_walk * std::sqrt(dt);
  const double sigma_ba = options.model.accel_bias_random_walk * std::sqrt(dt);

  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto gaussian3 = [&] {
    const double x = normal(rng), y = normal(rng), z = normal(rng);
    return Eigen::Vector3d(x, y, z);
  };

  std::vector<sensor::ImuSample> samples;
  samples.reserve(static_cast<std::size_t>(n));
  Eigen::Vector3d b_g = options.initial_gyro_bias, b_a = options.initial_accel_bias;
  for (int k = 0; k < n; ++k) {
    sensor::ImuSample s;
    s.t = k * dt;
    const Eigen::Matrix3d R_w_b = trajectory.R_w_b(s.t);
    s.gyro = trajectory.angular_velocity_b(s.t) + b_g + sigma_g * gaussian3();
    s.accel = R_w_b.transpose() * (trajectory.acceleration_w(s.t) - options.gravity_w) + b_a +
              sigma_a * gaussian3();
    s.gyro_bias = b_g;
    s.accel_bias = b_a;
    samples.push_back(s);
    b_g += sigma_bg * gaussian3();
    b_a += sigma_ba * gaussian3();
  }
  return samples;
}

}  // namespace sim
}  // namespace plucker
