// libFuzzer target: trajectory files (KITTI poses, TUM) through io/trajectory_io.h. Built as a
// fuzzer with -DPLUCKER_BUILD_FUZZERS=ON (clang, cmake/Fuzzers.cmake); io/fuzz_test.cc runs the
// same entry point as a unit test.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "plucker/io/fuzz_util.h"
#include "plucker/io/trajectory_io.h"

namespace plucker {
namespace io {
namespace fuzz {

std::vector<std::string> PoseSeeds() {
  return {"1 0 0 0 0 1 0 0 0 0 1 0\n0.99965 -0.0264 0 1.5 0.0264 0.99965 0 0.1 0 0 1 0\n",
          "# timestamp tx ty tz qx qy qz qw\n0.0 0 0 0 0 0 0 1\n0.1 1.0 0.1 0 0 0 0.0499792 "
          "0.99875\n"};
}

int PoseOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  for (TrajectoryFormat f :
       {TrajectoryFormat::kAuto, TrajectoryFormat::kKitti, TrajectoryFormat::kTum}) {
    try {
      const Trajectory tr = ParseTrajectory(text, "fuzz_poses.txt", f);
      Check(tr.times.empty() || tr.times.size() == tr.poses.size(), "times/poses sizes");
      for (const SE3d& T : tr.poses) {
        Check(T.translation().allFinite() && T.rotation().coeffs().allFinite(), "non-finite pose");
        Check(std::abs(T.rotation().norm() - 1.0) < 1e-6, "quaternion not unit");
      }
      CheckTimes(tr.times);
    } catch (const IoError&) {
    }
  }
  return 0;
}

}  // namespace fuzz
}  // namespace io
}  // namespace plucker

PLUCKER_FUZZ_TARGET("pose", PoseSeeds, PoseOneInput)
