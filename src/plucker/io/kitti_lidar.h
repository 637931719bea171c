// KITTI odometry LiDAR files.
//
//   velodyne/NNNNNN.bin : float32 little-endian records `x y z intensity` (16 bytes each), in the
//                         Velodyne frame (x forward, y left, z up), in firing order.
//   calib.txt           : lines `KEY: numbers`; `Tr:` holds 12 numbers, the 3x4 row-major matrix
//                         of T_cam0_velo (velodyne -> left camera). P0..P3 are ignored.
//   times.txt           : one timestamp (seconds) a line, finite and non-decreasing.
//
// Every function throws io::IoError naming the file and the problem.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "plucker/geometry/se3.h"
#include "plucker/io/io_error.h"
#include "plucker/io/scan_stats.h"
#include "plucker/sensor/lidar_scan.h"

namespace plucker {
namespace io {

// Parses the bytes of a .bin file; `name` is used in error messages. Errors: size not a multiple
// of 16 bytes (truncated), no record (empty scan), no finite record. NaN/Inf records are dropped
// and counted in `stats`. The scan has points and intensity; ring/time are empty.
LidarScan ParseKittiBin(const std::string& bytes, const std::string& name,
                        ScanReadStats* stats = nullptr);
// The same into an existing scan, reusing the capacity of its channels (no allocation once they
// are large enough: a sequence reader keeps one scan across frames). On error *scan is
// unspecified.
void ParseKittiBin(const std::string& bytes, const std::string& name, LidarScan* scan,
                   ScanReadStats* stats = nullptr);
// Reads a .bin file (adds "cannot open" / read errors to the above).
LidarScan ReadKittiBin(const std::string& path, ScanReadStats* stats = nullptr);

// Encodes / writes a scan as a .bin (intensity 0 when the scan has none). Write is atomic.
std::string SerializeKittiBin(const LidarScan& scan);
void WriteKittiBin(const std::string& path, const LidarScan& scan);

// calib.txt: the `Tr` entry as T_cam0_velo, its rotation re-orthonormalised (rejected when far
// from a rotation: max |R^T R - I| > 1e-2 or det <= 0). Returns std::nullopt when the file has no
// `Tr` line (not an error). Malformed numbers / wrong count / NaN in `Tr` -> IoError.
std::optional<SE3d> ParseKittiCalibTr(const std::string& text, const std::string& name);
std::optional<SE3d> ReadKittiCalibTr(const std::string& path);
// Writes a calib.txt holding only `Tr: ...` (12 numbers, %.17g).
void WriteKittiCalibTr(const std::string& path, const SE3d& T_cam0_velo);

// times.txt: one number a line (blank lines ignored); non-numeric, NaN/Inf or decreasing -> IoError
// naming the file and the line number.
std::vector<double> ParseKittiTimes(const std::string& text, const std::string& name);
std::vector<double> ReadKittiTimes(const std::string& path);
void WriteKittiTimes(const std::string& path, const std::vector<double>& times);

// Reads a whole file into a string; IoError if it cannot be opened or read.
std::string ReadFileToString(const std::string& path);
// The same into `*bytes`, reusing its capacity (one allocation for a sequence of similar files).
void ReadFileInto(const std::string& path, std::string* bytes);

}  // namespace io
}  // namespace plucker
