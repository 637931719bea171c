// libFuzzer target: KITTI .bin scans, calib.txt and times.txt parsers. Built as a fuzzer with
// -DPLUCKER_BUILD_FUZZERS=ON (clang, cmake/Fuzzers.cmake); io/fuzz_test.cc runs the same entry
// point as a unit test.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "plucker/io/fuzz_util.h"
#include "plucker/io/kitti_lidar.h"

namespace plucker {
namespace io {
namespace fuzz {

std::vector<std::string> KittiBinSeeds() {
  std::string bin;
  const float recs[3][4] = {{1.5f, -2.0f, 0.25f, 0.3f}, {10, 20, -1.7f, 0}, {-5, 0.1f, 3, 1}};
  bin.append(reinterpret_cast<const char*>(recs), sizeof(recs));
  return {bin, "P0: 1 0 0 0 0 1 0 0 0 0 1 0\nTr: 0 -1 0 0.1 0 0 -1 0.2 1 0 0 0.3\n",
          "0.0\n0.1037\n0.2073\n"};
}

int KittiBinOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    ScanReadStats stats;
    const LidarScan scan = ParseKittiBin(bytes, "fuzz.bin", &stats);
    Check(!scan.empty() && scan.intensity.size() == scan.size(), "bin: sizes");
    Check(stats.points_in_file == scan.size() + stats.non_finite_dropped, "bin: stats");
    for (const auto& p : scan.points) Check(p.allFinite(), "bin: non-finite point passed on");
  } catch (const IoError&) {
  }
  try {
    const std::optional<SE3d> T = ParseKittiCalibTr(bytes, "fuzz_calib.txt");
    if (T) {
      const Eigen::Matrix3d R = T->RotationMatrix();
      Check(R.allFinite() && T->translation().allFinite(), "calib: non-finite");
      Check((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-6,
            "calib: not a rotation");
    }
  } catch (const IoError&) {
  }
  try {
    CheckTimes(ParseKittiTimes(bytes, "fuzz_times.txt"));
  } catch (const IoError&) {
  }
  return 0;
}

}  // namespace fuzz
}  // namespace io
}  // namespace plucker

PLUCKER_FUZZ_TARGET("kitti_bin", KittiBinSeeds, KittiBinOneInput)
