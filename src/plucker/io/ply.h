// Stanford .ply point clouds: the subset `element vertex N` with float/double properties x y z and
// an optional `intensity` (any scalar type), format ascii 1.0 or binary_little_endian 1.0.
// Used for `plucker lidar --map map.ply`. The reader accepts exactly what the writer produces
// plus other vertex properties (skipped) and other elements AFTER the vertices (ignored); lists
// in the vertex element and big-endian files are rejected with a clear IoError.
#pragma once

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "plucker/io/io_error.h"
#include "plucker/io/scan_stats.h"
#include "plucker/sensor/lidar_scan.h"

namespace plucker {
namespace io {

enum class PlyFormat { kBinaryLittleEndian, kAscii };

// Writes x y z (float32) and, when `intensity` is non-empty (same size), intensity (float32).
// Atomic; IoError on a size mismatch or a write failure.
void WritePly(const std::string& path, const std::vector<Eigen::Vector3d>& points,
              const std::vector<float>& intensity = {},
              PlyFormat format = PlyFormat::kBinaryLittleEndian);
void WritePly(const std::string& path, const LidarScan& cloud,
              PlyFormat format = PlyFormat::kBinaryLittleEndian);
// 3D line segments as an ASCII .ply: two vertices per segment (x y z, float) and an `edge` element
// (vertex1 vertex2), which MeshLab and CloudCompare draw as lines. (The reader above does not read
// it back.) Atomic; IoError on a write failure.
void WriteSegmentsPly(const std::string& path,
                      const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& segments);

std::string SerializePly(const std::vector<Eigen::Vector3d>& points,
                         const std::vector<float>& intensity, PlyFormat format);

// Reads points (+ intensity when present). Non-finite points are dropped and counted.
LidarScan ParsePly(const std::string& bytes, const std::string& name,
                   ScanReadStats* stats = nullptr);
LidarScan ReadPly(const std::string& path, ScanReadStats* stats = nullptr);

}  // namespace io
}  // namespace plucker
