// Point Cloud Library .pcd files (format version 0.7, also accepts 0.5/0.6 headers).
//
// Header lines (in this order in valid files, '#' comments allowed): VERSION, FIELDS, SIZE, TYPE,
// COUNT (optional, default 1), WIDTH, HEIGHT, VIEWPOINT (optional), POINTS (optional, must equal
// WIDTH*HEIGHT), DATA ascii|binary|binary_compressed. binary_compressed (LZF, field-major) is
// decompressed by our own LZF decoder.
//
// Fields read: x y z (required; float or double), intensity (optional; any numeric type),
// ring (optional; integer or float), time or t (optional; per-point time). Other fields are
// skipped. Point time conventions: float/double `time`/`t` are seconds; an unsigned-integer `t`
// (Ouster) is nanoseconds. Times are made relative to the scan start: when some time is negative
// (times relative to the sweep end) or all are > 1 s (absolute stamps), the minimum is subtracted
// and, for absolute stamps, stored as the scan timestamp. Points with a NaN/Inf coordinate are
// dropped and counted (organised clouds use NaN for no-return).
//
// Errors (IoError naming the file and the problem): malformed/missing header entries, x/y/z
// missing, SIZE/TYPE/COUNT mismatches or unsupported sizes, WIDTH*HEIGHT != POINTS, truncated
// data, corrupt compressed data, non-numeric ASCII values, and empty clouds.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "plucker/io/io_error.h"
#include "plucker/io/scan_stats.h"
#include "plucker/sensor/lidar_scan.h"

namespace plucker {
namespace io {

enum class PcdEncoding { kAscii, kBinary, kBinaryCompressed };

struct PcdField {
  std::string name;
  int size = 4;     // bytes per element: 1, 2, 4, 8
  char type = 'F';  // 'F' float, 'I' signed, 'U' unsigned
  int count = 1;    // elements
};

struct PcdHeader {
  std::string version;
  std::vector<PcdField> fields;
  std::size_t width = 0, height = 0, points = 0;
  PcdEncoding encoding = PcdEncoding::kAscii;
  std::size_t data_offset = 0;  // byte offset of the data section in the file
  bool HasField(const std::string& name) const;
  bool has_time() const { return HasField("time") || HasField("t"); }
};

// Parses the header only (reads at most the first few KB when given a path).
PcdHeader ParsePcdHeader(const std::string& bytes, const std::string& name);
PcdHeader ReadPcdHeader(const std::string& path);

// Parses a whole .pcd file held in memory; `name` is used in error messages.
LidarScan ParsePcd(const std::string& bytes, const std::string& name,
                   ScanReadStats* stats = nullptr);
// The same into an existing scan, reusing the capacity of its channels (a sequence reader keeps
// one scan across frames). On error *scan is unspecified.
void ParsePcd(const std::string& bytes, const std::string& name, LidarScan* scan,
              ScanReadStats* stats = nullptr);
LidarScan ReadPcd(const std::string& path, ScanReadStats* stats = nullptr);

// Writes x y z as float32, plus `intensity` (float32), `ring` (uint16) and `time` (float64,
// seconds from the scan start) when the scan has them. kBinaryCompressed is not written
// (IoError); use kBinary or kAscii. Write is atomic.
std::string SerializePcd(const LidarScan& scan, PcdEncoding encoding = PcdEncoding::kBinary);
void WritePcd(const std::string& path, const LidarScan& scan,
              PcdEncoding encoding = PcdEncoding::kBinary);

// LZF decompression (as used by PCD binary_compressed). Returns false on corrupt input or when
// the output would not be exactly `expected_size` bytes. Exposed for tests and fuzzing.
bool LzfDecompress(const unsigned char* in, std::size_t in_size, std::size_t expected_size,
                   std::string* out);

}  // namespace io
}  // namespace plucker
