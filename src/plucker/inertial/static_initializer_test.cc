#include "plucker/inertial/static_initializer.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <stdexcept>

#include "plucker/inertial/gravity.h"
#include "plucker/io/euroc_imu.h"

namespace plucker {
namespace inertial {
namespace {

constexpr double kDeg = M_PI / 180.0;

struct StillLog {
  Eigen::Matrix3d R_w_b;
  Eigen::Vector3d gyro_bias{0.004, -0.02, 0.07};
  Eigen::Vector3d accel_bias{-0.02, 0.07, 0.04};
  std::vector<sensor::ImuSample> imu;
};

// 200 Hz: still for still_seconds (white noise with the spread of a vibrating drone), then
// shaken (accelerations of several m/s^2, rotation rates of 1 rad/s) until total_seconds.
StillLog MakeLog(double still_seconds, double total_seconds, std::uint32_t seed = 3) {
  StillLog log;
  log.R_w_b = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) *
               Eigen::AngleAxisd(-1.1, Eigen::Vector3d::UnitY()) *
               Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()))
                  .toRotationMatrix();
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01;
  const Eigen::Vector3d f_b = log.R_w_b.transpose() * Eigen::Vector3d(0, 0, 9.81);
  for (int k = 0; k * 0.005 <= total_seconds; ++k) {
    sensor::ImuSample s;
    s.t = 10.0 + k * 0.005;
    const Eigen::Vector3d ng(n01(rng), n01(rng), n01(rng)), na(n01(rng), n01(rng), n01(rng));
    s.gyro = log.gyro_bias + 0.03 * ng;
    s.accel = f_b + log.accel_bias + 0.4 * na;
    if (k * 0.005 >= still_seconds) {
      const double t = k * 0.005 - still_seconds;
      s.gyro += Eigen::Vector3d(std::sin(3 * t), std::cos(2 * t), 0.5);
      s.accel += 4.0 * Eigen::Vector3d(std::sin(5 * t), std::cos(4 * t), std::sin(7 * t));
    }
    log.imu.push_back(s);
  }
  return log;
}

Eigen::Vector3d UpB(const Eigen::Matrix3d& R_w_b) { return R_w_b.transpose().col(2); }

TEST(GravityAlignedRotation, MapsTheUpVectorToZWithZeroYaw) {
  std::mt19937 rng(1);
  std::normal_distribution<double> n01;
  int checked = 0;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d u = Eigen::Vector3d(n01(rng), n01(rng), n01(rng)).normalized();
    const Eigen::Matrix3d R = GravityAlignedRotation(3.0 * u);
    EXPECT_NEAR((R.transpose() * Eigen::Vector3d::UnitZ() - u).norm(), 0.0, 1e-12);
    EXPECT_NEAR((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    // ZYX yaw = atan2(R(1,0), R(0,0)) = 0: the body x axis has no world y component.
    EXPECT_NEAR(R(1, 0), 0.0, 1e-12);
    EXPECT_GE(R(0, 0), -1e-12);
    ++checked;
  }
  EXPECT_EQ(checked, 200);
  // The body x axis vertical (pitch +-90 deg): still a rotation with R^T e_z = u.
  const Eigen::Matrix3d R = GravityAlignedRotation(Eigen::Vector3d(-1, 0, 0));
  EXPECT_NEAR((R.transpose() * Eigen::Vector3d::UnitZ() - Eigen::Vector3d(-1, 0, 0)).norm(), 0.0,
              1e-12);
  EXPECT_THROW(GravityAlignedRotation(Eigen::Vector3d::Zero()), std::invalid_argument);
}

TEST(StaticInitializer, FindsTheStillSpanAndEstimatesGyroBiasAndTilt) {
  const StillLog log = MakeLog(3.0, 6.0);
  const StaticInitResult r = InitializeStatic(log.imu);
  ASSERT_TRUE(r.success()) << r.message;
  EXPECT_EQ(r.blocks_still, 12);                         // 3 s of 0.25 s blocks
  EXPECT_NEAR(r.still_end - r.still_begin, 2.75, 1e-9);  // the last still block is dropped
  EXPECT_EQ(r.samples_used, 550);
  EXPECT_GT(r.first_moving_block_accel_std, 1.5);
  // Gyro bias: the mean, within 4 sigma of its own covariance.
  const Eigen::Vector3d dg = r.bias.gyro - log.gyro_bias;
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(std::abs(dg(i)), 4.0 * std::sqrt(r.gyro_bias_covariance(i, i))) << i;
  }
  EXPECT_NEAR(r.gyro_bias_covariance(0, 0), 0.03 * 0.03 / 550, 0.3 * 0.03 * 0.03 / 550);
  EXPECT_NEAR(r.gyro_std.x(), 0.03, 0.005);
  EXPECT_NEAR(r.accel_std.y(), 0.4, 0.05);
  // The up direction errs by the horizontal accelerometer bias over |g| (not observable), plus
  // the noise of the mean (0.4 / sqrt(550) / 9.81 = 1.7e-3 rad per axis).
  const Eigen::Vector3d u = UpB(log.R_w_b);
  const Eigen::Vector3d b_h = log.accel_bias - u.dot(log.accel_bias) * u;
  const double tilt_error = AngleBetween(UpB(r.R_w_b), u);
  EXPECT_NEAR(tilt_error, b_h.norm() / 9.81, 3.5e-3);
  EXPECT_LT(tilt_error, 3.0 * r.tilt_sigma);
  EXPECT_NEAR((r.up_b - UpB(r.R_w_b)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((r.gravity_b + 9.81 * r.up_b).norm(), 0.0, 1e-12);
  // The accelerometer bias along gravity is observed; the horizontal part is the prior (zero).
  EXPECT_NEAR(r.bias.accel.dot(r.up_b), u.dot(log.accel_bias), 0.06);
  EXPECT_NEAR((r.bias.accel - r.bias.accel.dot(r.up_b) * r.up_b).norm(), 0.0, 1e-12);
  std::printf("tilt error %.3f deg (horizontal bias %.3f m/s^2 -> %.3f deg), sigma %.3f deg\n",
              tilt_error / kDeg, b_h.norm(), b_h.norm() / 9.81 / kDeg, r.tilt_sigma / kDeg);
}

TEST(StaticInitializer, AKnownHorizontalBiasRemovesTheTiltError) {
  const StillLog log = MakeLog(3.0, 6.0);
  StaticInitOptions o;
  o.accel_bias_prior = log.accel_bias;
  o.accel_bias_prior_sigma = 0.0;
  const StaticInitResult r = InitializeStatic(log.imu, o);
  ASSERT_TRUE(r.success()) << r.message;
  const double tilt_error = AngleBetween(UpB(r.R_w_b), UpB(log.R_w_b));
  EXPECT_LT(tilt_error, 3.0 * r.tilt_sigma);
  EXPECT_LT(tilt_error, 0.1 * kDeg);
  EXPECT_NEAR((r.bias.accel - log.accel_bias).norm(), 0.0, 0.06);
}

TEST(StaticInitializer, FailsWhenMovingFromTheStart) {
  const StillLog log = MakeLog(0.0, 4.0);
  const StaticInitResult r = InitializeStatic(log.imu);
  EXPECT_EQ(r.status, StaticInitStatus::kNotStill);
  EXPECT_EQ(r.blocks_still, 0);
  EXPECT_NE(r.message.find("still for 0.00 s"), std::string::npos) << r.message;
}

TEST(StaticInitializer, AStillSpanShorterThanTheMinimumFails) {
  const StillLog log = MakeLog(1.0, 4.0);
  const StaticInitResult r = InitializeStatic(log.imu);
  EXPECT_EQ(r.status, StaticInitStatus::kNotStill) << r.message;
  EXPECT_EQ(r.blocks_still, 4);
  // Starting later inside the motion: nothing still either.
  EXPECT_EQ(InitializeStatic(log.imu, {}, 12.0).status, StaticInitStatus::kNotStill);
}

TEST(StaticInitializer, AMovingImageFlagEndsTheStillSpan) {
  const StillLog log = MakeLog(3.0, 6.0);
  StaticInitOptions o;
  o.min_still_seconds = 0.5;
  const StaticInitResult r =
      InitializeStatic(log.imu, o, -1e300, {{10.5, true}, {11.1, false}, {11.6, true}});
  ASSERT_TRUE(r.success()) << r.message;
  EXPECT_EQ(r.blocks_still, 4);           // [11.0, 11.25) holds the moving frame
  EXPECT_NEAR(r.still_end, 10.75, 1e-9);  // minus the dropped block
}

TEST(StaticInitializer, ASpecificForceFarFromGravityIsRejected) {
  StillLog log = MakeLog(3.0, 6.0);
  for (sensor::ImuSample& s : log.imu) s.accel /= 9.81;  // readings in g, not m/s^2
  StaticInitOptions o;
  o.max_accel_std = 1.0;
  const StaticInitResult r = InitializeStatic(log.imu, o);
  EXPECT_EQ(r.status, StaticInitStatus::kGravityMismatch);
  EXPECT_NE(r.message.find("1.0"), std::string::npos) << r.message;
}

TEST(StaticInitializer, BadInputThrowsOrFailsCleanly) {
  StillLog log = MakeLog(3.0, 6.0);
  EXPECT_EQ(InitializeStatic({}).status, StaticInitStatus::kTooFewSamples);
  std::vector<sensor::ImuSample> short_log(log.imu.begin(), log.imu.begin() + 10);
  EXPECT_EQ(InitializeStatic(short_log).status, StaticInitStatus::kTooFewSamples);
  log.imu[100].t = log.imu[99].t;
  EXPECT_THROW(InitializeStatic(log.imu), std::invalid_argument);
  log = MakeLog(3.0, 6.0);
  log.imu[5].accel.x() = std::nan("");
  EXPECT_THROW(InitializeStatic(log.imu), std::invalid_argument);
  StaticInitOptions o;
  o.block_seconds = 0.0;
  EXPECT_THROW(InitializeStatic(MakeLog(3.0, 6.0).imu, o), std::invalid_argument);
}

// Real data: EuRoC V1_01 stands still (rotors running) for ~5 s before take-off; the ground truth
// (re-estimated over the whole flight) gives R_w_b and the biases.
TEST(StaticInitializer, EurocV101StillPeriod) {
  const std::string dir = std::string(PLUCKER_SHARED_DATA_DIR) + "/euroc-v101-head";
  if (!std::ifstream(dir + "/mav0/imu0/data.csv")) {
    GTEST_SKIP() << "no " << dir << " (real data absent)";
  }
  const io::EurocImuRecording rec = io::ReadEurocImuRecording(dir);
  ASSERT_FALSE(rec.ground_truth.empty());
  const StaticInitResult r = InitializeStatic(rec.imu);
  ASSERT_TRUE(r.success()) << r.message;
  EXPECT_GT(r.still_end - r.still_begin, 4.0);
  EXPECT_LT(r.still_end - r.still_begin, 6.0);
  Eigen::Vector3d gt_gyro = Eigen::Vector3d::Zero(), gt_up = Eigen::Vector3d::Zero(),
                  gt_accel = Eigen::Vector3d::Zero();
  int n = 0;
  for (const sensor::BodyState& s : rec.ground_truth) {
    if (s.t < r.still_begin || s.t >= r.still_end) continue;
    gt_gyro += s.bias.gyro;
    gt_accel += s.bias.accel;
    gt_up += UpB(s.T_w_b.RotationMatrix());
    ++n;
  }
  ASSERT_GT(n, 60);
  gt_gyro /= n;
  gt_accel /= n;
  const double gyro_error = (r.bias.gyro - gt_gyro).norm();
  const double tilt_error = AngleBetween(r.up_b, gt_up);
  const Eigen::Vector3d u = gt_up.normalized();
  const double gt_horizontal = (gt_accel - gt_accel.dot(u) * u).norm();
  // With the ground truth's accelerometer bias as the prior (what a calibrated bias would give).
  StaticInitOptions o;
  o.accel_bias_prior = gt_accel;
  const StaticInitResult known = InitializeStatic(rec.imu, o);
  const double tilt_error_known = AngleBetween(known.up_b, gt_up);
  std::printf(
      "EuRoC V1_01 still %.2f s, %d samples: gyro bias error %.2e rad/s; gravity direction "
      "error %.3f deg (ground truth's horizontal accel bias %.3f m/s^2 = %.3f deg); with that "
      "bias known %.3f deg; accel bias along gravity %.4f (ground truth %.4f) m/s^2\n",
      r.still_end - r.still_begin, r.samples_used, gyro_error, tilt_error / kDeg, gt_horizontal,
      gt_horizontal / 9.81 / kDeg, tilt_error_known / kDeg, r.bias.accel.dot(r.up_b),
      gt_accel.dot(u));
  EXPECT_LT(gyro_error, 2e-3);
  // The target is 0.5 deg; from the IMU alone 0.61 deg is measured, 0.43 deg of which is the
  // unobservable horizontal bias (docs/math/vi-initialisation.md).
  EXPECT_LT(tilt_error, 0.7 * kDeg);
  EXPECT_LT(tilt_error_known, 0.3 * kDeg);
  EXPECT_NEAR(r.bias.accel.dot(r.up_b), gt_accel.dot(u), 0.02);
}

}  // namespace
}  // namespace inertial
}  // namespace plucker
