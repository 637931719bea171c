#include "plucker/io/euroc_imu.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "plucker/io/io_error.h"

namespace plucker {
namespace io {
namespace {

const char kImu[] =
    "#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z\n"
    "1000000000,0.1,0.2,0.3,9.8,0.0,-0.1\n"
    "1005000000,0.1,0.2,0.3,9.7,0.1,-0.2\r\n";

const char kGt[] =
    "#time(ns),px,py,pz,qw,qx,qy,qz,vx,vy,vz,bwx,bwy,bwz,bax,bay,baz\n"
    "1000000000,1,2,3,0,1,0,0,0.1,0.2,0.3,0.01,0.02,0.03,0.1,0.2,0.3\n";

const char kYaml[] =
    "%YAML:1.0\nsensor_type: imu\nT_BS:\n  cols: 4\n  rows: 4\n"
    "  data: [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]\n"
    "rate_hz: 200\ngyroscope_noise_density: 1.6968e-04\ngyroscope_random_walk: 1.9393e-05\n"
    "accelerometer_noise_density: 2.0000e-3\naccelerometer_random_walk: 3.0000e-3\n";

TEST(EurocImu, ParsesSamplesInSecondsSinceTheOrigin) {
  const auto s = ParseEurocImuCsv(kImu, "imu.csv", 1000000000);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_DOUBLE_EQ(s[0].t, 0.0);
  EXPECT_NEAR(s[1].t, 0.005, 1e-15);
  EXPECT_EQ(s[1].gyro, Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_EQ(s[1].accel, Eigen::Vector3d(9.7, 0.1, -0.2));
}

TEST(EurocImu, ParsesGroundTruthWithQuaternionWFirst) {
  const auto g = ParseEurocGroundTruthCsv(kGt, "gt.csv", 0);
  ASSERT_EQ(g.size(), 1u);
  EXPECT_DOUBLE_EQ(g[0].t, 1.0);
  // q = (w 0, x 1): a rotation of pi about x.
  EXPECT_NEAR(g[0].T_w_b.rotation().x(), 1.0, 1e-15);
  EXPECT_EQ(g[0].T_w_b.translation(), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(g[0].v_w, Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_EQ(g[0].bias.gyro, Eigen::Vector3d(0.01, 0.02, 0.03));
  EXPECT_EQ(g[0].bias.accel, Eigen::Vector3d(0.1, 0.2, 0.3));
}

TEST(EurocImu, ParsesTheNoiseFigures) {
  const sensor::ImuModel m = ParseEurocImuYaml(kYaml, "sensor.yaml");
  EXPECT_EQ(m.rate_hz, 200.0);
  EXPECT_EQ(m.gyro_noise_density, 1.6968e-04);
  EXPECT_EQ(m.gyro_bias_random_walk, 1.9393e-05);
  EXPECT_EQ(m.accel_noise_density, 2.0e-3);
  EXPECT_EQ(m.accel_bias_random_walk, 3.0e-3);
}

// Every bad input is refused with a message that names the place and the problem.
void ExpectError(const std::function<void()>& parse, const std::string& where,
                 const std::string& problem) {
  try {
    parse();
    ADD_FAILURE() << "no error for " << where;
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(problem), std::string::npos) << e.what();
  }
}

TEST(EurocImu, RefusesBadCsv) {
  ExpectError([] { ParseEurocImuCsv("1,2,3\n", "a.csv", 0); }, "a.csv:1", "3 fields, expected 7");
  ExpectError([] { ParseEurocImuCsv("x,1,2,3,4,5,6\n", "a.csv", 0); }, "a.csv:1", "bad timestamp");
  ExpectError([] { ParseEurocImuCsv("5,1,2,3,4,5,nan\n", "a.csv", 0); }, "a.csv:1", "bad number");
  ExpectError([] { ParseEurocImuCsv("5,1,2,3,4,5,6\n5,1,2,3,4,5,6\n", "a.csv", 0); }, "a.csv:2",
              "does not increase");
  ExpectError([] { ParseEurocImuCsv("#only a header\n", "a.csv", 0); }, "a.csv", "empty file");
  ExpectError([] { ParseEurocGroundTruthCsv("1,1,2,3,0,0,0,0,0,0,0,0,0,0,0,0,0\n", "g.csv", 0); },
              "g.csv:1", "zero or overflowing quaternion");
}

TEST(EurocImu, AcceptsAMissingTbs) {
  std::string no_tbs = kYaml;
  no_tbs.erase(no_tbs.find("T_BS"), no_tbs.find("rate_hz") - no_tbs.find("T_BS"));
  EXPECT_EQ(ParseEurocImuYaml(no_tbs, "s.yaml").rate_hz, 200.0);
}

TEST(EurocImu, RefusesBadYaml) {
  std::string missing = kYaml;
  missing.erase(missing.find("rate_hz"), std::string("rate_hz: 200\n").size());
  ExpectError([&] { ParseEurocImuYaml(missing, "s.yaml"); }, "s.yaml", "missing key 'rate_hz'");
  std::string negative = kYaml;
  negative.replace(negative.find("2.0000e-3"), 9, "-2.0e-3");
  ExpectError([&] { ParseEurocImuYaml(negative, "s.yaml"); }, "s.yaml", "must be positive");
  std::string rotated = kYaml;
  rotated.replace(rotated.find("[1.0, 0.0"), 9, "[0.0, 1.0");
  ExpectError([&] { ParseEurocImuYaml(rotated, "s.yaml"); }, "s.yaml", "T_BS is not the identity");
  ExpectError([] { ParseEurocImuYaml("[1, 2", "s.yaml"); }, "s.yaml", "not YAML");
  // Found by the fuzzer: a scalar T_BS was subscripted and threw yaml-cpp's BadSubscript.
  ExpectError([] { ParseEurocImuYaml("T_BS: 3\nrate_hz: 200\n", "s.yaml"); }, "s.yaml",
              "T_BS must be a map");
  ExpectError([] { ReadEurocImuRecording("/nonexistent/euroc"); }, "/nonexistent/euroc",
              "not a EuRoC folder");
}

TEST(EurocImu, ReadsTheSharedExtract) {
  const std::string dir = std::string(PLUCKER_SHARED_DATA_DIR) + "/euroc-v101-head";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << "no shared data at " << dir;
  const EurocImuRecording r = ReadEurocImuRecording(dir);
  EXPECT_EQ(r.origin_ns, 1403715273262142976);
  EXPECT_EQ(r.imu.size(), 29120u);
  EXPECT_EQ(r.ground_truth.size(), 2895u);
  EXPECT_EQ(r.imu_model.gyro_noise_density, 1.6968e-04);
  EXPECT_NEAR(r.imu.back().t - r.imu.front().t, 145.6, 0.1);
  // At rest at the start: the accelerometer reads about +9.81 m/s^2 in magnitude.
  EXPECT_NEAR(r.imu.front().accel.norm(), 9.81, 0.2);
}

}  // namespace
}  // namespace io
}  // namespace plucker
