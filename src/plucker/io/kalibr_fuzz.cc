// libFuzzer target: Kalibr camchain.yaml and imu.yaml through io/kalibr_calibration.h. Built as a
// fuzzer with -DPLUCKER_BUILD_FUZZERS=ON (clang, cmake/Fuzzers.cmake); io/fuzz_test.cc runs the
// same entry point as a unit test.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "plucker/io/fuzz_util.h"
#include "plucker/io/io_error.h"
#include "plucker/io/kalibr_calibration.h"

namespace plucker {
namespace io {
namespace fuzz {

std::vector<std::string> KalibrSeeds() {
  return {
      "cam0:\n  T_cam_imu:\n  - [0.0148655429818, 0.999557249008, -0.0257744366974, 0.0652]\n"
      "  - [-0.999880929698, 0.0149672133247, 0.00375618835797, -0.0207]\n"
      "  - [0.00414029679422, 0.025715529948, 0.999660727178, -0.0081]\n"
      "  - [0.0, 0.0, 0.0, 1.0]\n  camera_model: pinhole\n"
      "  distortion_coeffs: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]\n"
      "  distortion_model: radtan\n  intrinsics: [458.654, 457.296, 367.215, 248.375]\n"
      "  resolution: [752, 480]\n  timeshift_cam_imu: 0.0\n"
      "cam1:\n  T_cn_cnm1: [[1, 0, 0, -0.11], [0, 0.6, -0.8, 0], [0, 0.8, 0.6, 0], [0, 0, 0, 1]]\n"
      "  camera_model: pinhole\n  distortion_coeffs: [0.0035, 0.0007, -0.0021, 0.0002]\n"
      "  distortion_model: equidistant\n  intrinsics: [190.98, 190.97, 254.93, 256.90]\n"
      "  resolution: [512, 512]\n",
      "accelerometer_noise_density: 2.0e-3\naccelerometer_random_walk: 3.0e-3\n"
      "gyroscope_noise_density: 1.6968e-04\ngyroscope_random_walk: 1.9393e-05\n"
      "update_rate: 200.0\n"};
}

int KalibrOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const KalibrCameraChain chain = ParseKalibrCameraChain(text, "fuzz_camchain.yaml");
    Check(!chain.cameras.empty(), "a chain without cameras");
    for (const KalibrCamera& c : chain.cameras) {
      Check(c.camera.IsValid(), "an invalid camera was accepted");
      Check(!c.T_b_c || (c.T_b_c->translation().allFinite() &&
                         std::abs(c.T_b_c->rotation().norm() - 1.0) < 1e-9),
            "a non-rigid T_b_c was accepted");
      Check(std::isfinite(c.timeshift_cam_imu), "non-finite time shift");
    }
  } catch (const IoError&) {
  }
  try {
    const sensor::ImuModel m = ParseKalibrImu(text, "fuzz_imu.yaml");
    Check(m.rate_hz > 0 && m.gyro_noise_density > 0 && m.accel_bias_random_walk > 0,
          "non-positive noise figure");
  } catch (const IoError&) {
  }
  return 0;
}

}  // namespace fuzz
}  // namespace io
}  // namespace plucker

PLUCKER_FUZZ_TARGET("kalibr", KalibrSeeds, KalibrOneInput)
