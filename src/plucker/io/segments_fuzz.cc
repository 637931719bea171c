// libFuzzer target: segment files (io/segments.h). Built as a fuzzer with
// -DPLUCKER_BUILD_FUZZERS=ON (clang, cmake/Fuzzers.cmake); io/fuzz_test.cc runs the same entry
// point as a unit test.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "plucker/io/fuzz_util.h"
#include "plucker/io/segments.h"

namespace plucker {
namespace io {
namespace fuzz {

std::vector<std::string> SegmentSeeds() {
  return {"0 106 28 103\n0 108 26 105\n22.4 146.7 0 149\n",
          "# plucker lines detect\n# detection_ms 12.5\n1.000,2.000,3.000,4.000\n"};
}

int SegmentOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const SegmentFile f = ParseSegments(text, "fuzz_segments.txt");
    for (const Eigen::Vector4d& s : f.segments) {
      Check(s.allFinite() && s.cwiseAbs().maxCoeff() <= 1e6, "bad segment accepted");
    }
    Check(!f.detection_ms || (std::isfinite(*f.detection_ms) && *f.detection_ms >= 0.0),
          "bad detection_ms accepted");
    // What was accepted is written and read back to the same segment count.
    Check(ParseSegments(FormatSegments(f), "again").segments.size() == f.segments.size(),
          "round trip");
  } catch (const IoError&) {
  }
  return 0;
}

}  // namespace fuzz
}  // namespace io
}  // namespace plucker

PLUCKER_FUZZ_TARGET("segments", SegmentSeeds, SegmentOneInput)
