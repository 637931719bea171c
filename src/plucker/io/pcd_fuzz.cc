// libFuzzer target: PCD (ascii, binary, binary_compressed) and PLY parsers. Built as a fuzzer
// with -DPLUCKER_BUILD_FUZZERS=ON (clang, cmake/Fuzzers.cmake); io/fuzz_test.cc runs the same
// entry point as a unit test.
#include <cstdint>
#include <string>
#include <vector>

#include "plucker/io/fuzz_util.h"
#include "plucker/io/pcd.h"
#include "plucker/io/ply.h"

namespace plucker {
namespace io {
namespace fuzz {

std::vector<std::string> PcdSeeds() {
  LidarScan scan;
  for (int i = 0; i < 4; ++i) {
    scan.points.emplace_back(1.0 + i, -0.5 * i, 0.25);
    scan.intensity.push_back(0.1f * i);
    scan.ring.push_back(i);
    scan.time.push_back(0.01 * i);
  }
  LidarScan plain;
  plain.points = scan.points;
  // binary_compressed: x y z field-major, one literal run.
  std::string raw;
  for (int f = 0; f < 3; ++f) {
    for (int i = 0; i < 2; ++i) {
      const float v = static_cast<float>(f + 10 * i);
      raw.append(reinterpret_cast<const char*>(&v), 4);
    }
  }
  std::string compressed =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA binary_compressed\n";
  const std::uint32_t sizes[2] = {static_cast<std::uint32_t>(raw.size() + 1),
                                  static_cast<std::uint32_t>(raw.size())};
  compressed.append(reinterpret_cast<const char*>(sizes), 8);
  compressed.push_back(static_cast<char>(raw.size() - 1));
  compressed += raw;
  return {SerializePcd(scan, PcdEncoding::kAscii),
          SerializePcd(scan, PcdEncoding::kBinary),
          SerializePcd(plain, PcdEncoding::kBinary),
          compressed,
          SerializePly(scan.points, scan.intensity, PlyFormat::kAscii),
          SerializePly(scan.points, {}, PlyFormat::kBinaryLittleEndian)};
}

void CheckScan(const LidarScan& s, const ScanReadStats& stats) {
  Check(!s.empty(), "empty scan returned");
  Check(s.intensity.empty() || s.intensity.size() == s.size(), "intensity size");
  Check(s.ring.empty() || s.ring.size() == s.size(), "ring size");
  Check(s.time.empty() || s.time.size() == s.size(), "time size");
  Check(stats.points_in_file == s.size() + stats.non_finite_dropped, "stats");
  for (const auto& p : s.points) Check(p.allFinite(), "non-finite point passed on");
  for (double t : s.time) Check(std::isfinite(t) && t >= 0.0, "bad point time");
}

int PcdOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    ScanReadStats stats;
    CheckScan(ParsePcd(bytes, "fuzz.pcd", &stats), stats);
  } catch (const IoError&) {
  }
  try {
    ScanReadStats stats;
    CheckScan(ParsePly(bytes, "fuzz.ply", &stats), stats);
  } catch (const IoError&) {
  }
  // The raw LZF decoder on the whole input (bounded output size).
  std::string out;
  LzfDecompress(data, size, size * 4 + 16, &out);
  return 0;
}

}  // namespace fuzz
}  // namespace io
}  // namespace plucker

PLUCKER_FUZZ_TARGET("pcd", PcdSeeds, PcdOneInput)
