#include "plucker/sim/imu.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "plucker/geometry/so3.h"

namespace plucker {
namespace sim {
namespace {

Trajectory TestTrajectory(SceneKind kind, double duration) {
  SceneOptions scene_options;
  scene_options.kind = kind;
  TrajectoryOptions options;
  options.duration = duration;
  return MakeTrajectory(options, MakeScene(scene_options, 2), 3);
}

ImuOptions NoiseFree() {
  ImuOptions o;
  o.model.gyro_noise_density = o.model.accel_noise_density = 0.0;
  o.model.gyro_bias_random_walk = o.model.accel_bias_random_walk = 0.0;
  return o;
}

TEST(ImuTest, SampleTimesCoverTheTrajectory) {
  const Trajectory tr = TestTrajectory(SceneKind::kRoom, 2.0);
  ImuOptions o;
  o.model.rate_hz = 100.0;
  const std::vector<sensor::ImuSample> s = SimulateImu(tr, o, 1);
  ASSERT_EQ(s.size(), 201u);
  EXPECT_EQ(s.front().t, 0.0);
  EXPECT_NEAR(s.back().t, 2.0, 1e-12);
}

// Noise-free samples integrated with the trapezoidal rule reproduce the trajectory.
TEST(ImuTest, NoiseFreeIntegrationReproducesTrajectory) {
  for (SceneKind kind : {SceneKind::kRoom, SceneKind::kFacades}) {
    const Trajectory tr = TestTrajectory(kind, 10.0);
    ImuOptions o = NoiseFree();
    o.initial_gyro_bias = Eigen::Vector3d(0.01, -0.02, 0.005);
    o.initial_accel_bias = Eigen::Vector3d(0.1, 0.05, -0.2);
    const std::vector<sensor::ImuSample> s = SimulateImu(tr, o, 1);
    const double dt = 1.0 / o.model.rate_hz;
    Eigen::Matrix3d R = tr.R_w_b(0.0);
    Eigen::Vector3d v = tr.velocity_w(0.0), p = tr.position_w(0.0);
    auto a_w = [&](const Eigen::Matrix3d& R_k, const sensor::ImuSample& x) {
      return Eigen::Vector3d(R_k * (x.accel - x.accel_bias) + o.gravity_w);
    };
    double max_rot = 0, max_pos = 0, max_vel = 0;
    for (std::size_t k = 0; k + 1 < s.size(); ++k) {
      EXPECT_EQ(s[k].gyro_bias, o.initial_gyro_bias);
      const Eigen::Vector3d w_mid =
          0.5 * (s[k].gyro - s[k].gyro_bias + s[k + 1].gyro - s[k + 1].gyro_bias);
      const Eigen::Matrix3d R_next = R * ExpSO3Matrix<double>(w_mid * dt);
      const Eigen::Vector3d v_next = v + 0.5 * dt * (a_w(R, s[k]) + a_w(R_next, s[k + 1]));
      p += 0.5 * dt * (v + v_next) + dt * dt / 12.0 * (a_w(R, s[k]) - a_w(R_next, s[k + 1]));
      v = v_next;
      R = R_next;
      const double t = s[k + 1].t;
      max_rot = std::max(max_rot, LogSO3(Eigen::Quaterniond(tr.R_w_b(t).transpose() * R)).norm());
      max_pos = std::max(max_pos, (p - tr.position_w(t)).norm());
      max_vel = std::max(max_vel, (v - tr.velocity_w(t)).norm());
    }
    EXPECT_LT(max_rot, 1e-4) << SceneKindName(kind);
    EXPECT_LT(max_vel, 2e-3) << SceneKindName(kind);
    EXPECT_LT(max_pos, 1e-3) << SceneKindName(kind);
    RecordProperty("max_pos_error_" + SceneKindName(kind), std::to_string(max_pos));
  }
}

TEST(ImuTest, NoiseStatisticsMatchDensities) {
  const Trajectory tr = TestTrajectory(SceneKind::kCorridor, 50.0);
  ImuOptions o;
  o.model.rate_hz = 200.0;
  o.model.gyro_noise_density = 2e-3;
  o.model.accel_noise_density = 3e-2;
  o.model.gyro_bias_random_walk = 1e-3;
  o.model.accel_bias_random_walk = 4e-2;
  const std::vector<sensor::ImuSample> s = SimulateImu(tr, o, 17);
  const std::vector<sensor::ImuSample> clean = SimulateImu(tr, NoiseFree(), 17);
  ASSERT_EQ(s.size(), clean.size());
  const double dt = 1.0 / o.model.rate_hz;
  double sum_g = 0, sum_a = 0, sq_g = 0, sq_a = 0, sq_bg = 0, sq_ba = 0;
  long n = 0, m = 0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const Eigen::Vector3d ng = s[k].gyro - clean[k].gyro - s[k].gyro_bias;
    const Eigen::Vector3d na = s[k].accel - clean[k].accel - s[k].accel_bias;
    sum_g += ng.sum();
    sum_a += na.sum();
    sq_g += ng.squaredNorm();
    sq_a += na.squaredNorm();
    n += 3;
    if (k + 1 < s.size()) {
      sq_bg += (s[k + 1].gyro_bias - s[k].gyro_bias).squaredNorm();
      sq_ba += (s[k + 1].accel_bias - s[k].accel_bias).squaredNorm();
      m += 3;
    }
  }
  const double sigma_g = o.model.gyro_noise_density / std::sqrt(dt);
  const double sigma_a = o.model.accel_noise_density / std::sqrt(dt);
  EXPECT_NEAR(std::sqrt(sq_g / n) / sigma_g, 1.0, 0.03);
  EXPECT_NEAR(std::sqrt(sq_a / n) / sigma_a, 1.0, 0.03);
  EXPECT_NEAR(sum_g / n / sigma_g, 0.0, 0.03);
  EXPECT_NEAR(sum_a / n / sigma_a, 0.0, 0.03);
  EXPECT_NEAR(std::sqrt(sq_bg / m) / (o.model.gyro_bias_random_walk * std::sqrt(dt)), 1.0, 0.03);
  EXPECT_NEAR(std::sqrt(sq_ba / m) / (o.model.accel_bias_random_walk * std::sqrt(dt)), 1.0, 0.03);
}

TEST(ImuTest, DeterministicGivenSeed) {
  const Trajectory tr = TestTrajectory(SceneKind::kRoom, 1.0);
  const auto a = SimulateImu(tr, ImuOptions(), 5), b = SimulateImu(tr, ImuOptions(), 5),
             c = SimulateImu(tr, ImuOptions(), 6);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].gyro, b[k].gyro);
    EXPECT_EQ(a[k].accel, b[k].accel);
    EXPECT_EQ(a[k].accel_bias, b[k].accel_bias);
  }
  EXPECT_NE(a[3].gyro, c[3].gyro);
}

TEST(ImuTest, StaticBodyMeasuresGravity) {
  SmoothSignal zero;
  const Trajectory still({zero, zero, zero}, zero, zero, zero, 1.0);
  const auto s = SimulateImu(still, NoiseFree(), 1);
  for (const sensor::ImuSample& x : s) {
    EXPECT_EQ(x.gyro, Eigen::Vector3d::Zero());
    EXPECT_NEAR((x.accel - Eigen::Vector3d(0, 0, 9.81)).norm(), 0.0, 1e-12);
  }
}

TEST(ImuTest, RejectsInvalidOptions) {
  const Trajectory tr = TestTrajectory(SceneKind::kRoom, 1.0);
  ImuOptions o;
  o.model.rate_hz = 0.0;
  EXPECT_THROW(SimulateImu(tr, o, 1), std::invalid_argument);
  o = ImuOptions();
  o.model.gyro_noise_density = -1.0;
  EXPECT_THROW(SimulateImu(tr, o, 1), std::invalid_argument);
  o = ImuOptions();
  o.gravity_w.x() = std::nan("");
  EXPECT_THROW(SimulateImu(tr, o, 1), std::invalid_argument);
}

}  // namespace
}  // namespace sim
}  // namespace plucker
