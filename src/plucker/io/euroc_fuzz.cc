// libFuzzer target: EuRoC IMU, ground-truth and camera CSV files and IMU sensor.yaml through
// io/euroc_imu.h and io/euroc_dataset.h. Built as a fuzzer with -DPLUCKER_BUILD_FUZZERS=ON (clang,
// cmake/Fuzzers.cmake); io/fuzz_test.cc runs the same entry point as a unit test.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "plucker/io/euroc_dataset.h"
#include "plucker/io/euroc_imu.h"
#include "plucker/io/fuzz_util.h"
#include "plucker/io/io_error.h"

namespace plucker {
namespace io {
namespace fuzz {

std::vector<std::string> EurocSeeds() {
  return {
      "#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z\n1000,0.1,0.2,0.3,9.8,0,-0.1\n"
      "6000,0.1,0.2,0.3,9.7,0.1,-0.2\n",
      "#time(ns),px,py,pz,qw,qx,qy,qz,vx,vy,vz,bwx,bwy,bwz,bax,bay,baz\n"
      "1000,1,2,3,1,0,0,0,0.1,0.2,0.3,0.01,0.02,0.03,0.1,0.2,0.3\n",
      "%YAML:1.0\nrate_hz: 200\ngyroscope_noise_density: 1.6968e-04\n"
      "gyroscope_random_walk: 1.9393e-05\naccelerometer_noise_density: 2.0e-3\n"
      "accelerometer_random_walk: 3.0e-3\n",
      "#timestamp [ns],filename\n1000,1000.png\n1000,1000.png\n900,x.png\n"};
}

int EurocOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    double last = -1e300;
    for (const sensor::ImuSample& s : ParseEurocImuCsv(text, "fuzz_imu.csv", 0)) {
      Check(std::isfinite(s.t) && s.gyro.allFinite() && s.accel.allFinite(), "non-finite sample");
      Check(s.t > last, "times do not increase");
      last = s.t;
    }
  } catch (const IoError&) {
  }
  try {
    for (const sensor::BodyState& s : ParseEurocGroundTruthCsv(text, "fuzz_gt.csv", 0)) {
      Check(std::abs(s.T_w_b.rotation().norm() - 1.0) < 1e-6, "quaternion not unit");
      Check(s.T_w_b.translation().allFinite() && s.v_w.allFinite(), "non-finite state");
    }
  } catch (const IoError&) {
  }
  try {
    // The image folder does not exist: every row is skipped or an error, none is kept.
    std::vector<FrameSkip> skipped;
    Check(
        ParseEurocCameraCsv(text, "fuzz_cam.csv", "/nonexistent-plucker-fuzz", 0, &skipped).empty(),
        "a frame without its image file was kept");
  } catch (const IoError&) {
  }
  try {
    const sensor::ImuModel m = ParseEurocImuYaml(text, "fuzz_sensor.yaml");
    Check(m.rate_hz > 0 && m.gyro_noise_density > 0 && m.accel_noise_density > 0,
          "non-positive noise figure");
  } catch (const IoError&) {
  }
  return 0;
}

}  // namespace fuzz
}  // namespace io
}  // namespace plucker

PLUCKER_FUZZ_TARGET("euroc", EurocSeeds, EurocOneInput)
