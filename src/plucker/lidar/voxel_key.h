// Integer voxel coordinates packed into one 64-bit hash key (internal to the lidar layer).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace plucker {
namespace lidar {

// 21 bits per axis (offset binary): +-2^20 voxels per axis, e.g. +-1048 km at 1 m voxels.
inline std::uint64_t PackVoxel(const Eigen::Vector3i& v) {
  constexpr std::int64_t kOffset = std::int64_t{1} << 20;
  constexpr std::uint64_t kMask = (std::uint64_t{1} << 21) - 1;
  const std::uint64_t x = static_cast<std::uint64_t>(v.x() + kOffset) & kMask;
  const std::uint64_t y = static_cast<std::uint64_t>(v.y() + kOffset) & kMask;
  const std::uint64_t z = static_cast<std::uint64_t>(v.z() + kOffset) & kMask;
  return (x << 42) | (y << 21) | z;
}

// Voxel coordinates, clamped to the packable range (no overflow for absurd inputs).
inline Eigen::Vector3i VoxelOf(const Eigen::Vector3d& p, double inv_size) {
  constexpr double kLimit = 1048000.0;
  auto cell = [&](double v) {
    return static_cast<int>(std::clamp(std::floor(v * inv_size), -kLimit, kLimit));
  };
  return Eigen::Vector3i(cell(p.x()), cell(p.y()), cell(p.z()));
}

// A cheap mixing hash for the packed key (robin_map's std::hash<uint64_t> is the identity).
struct VoxelKeyHash {
  std::size_t operator()(std::uint64_t k) const {
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdULL;
    k ^= k >> 33;
    return static_cast<std::size_t>(k);
  }
};

}  // namespace lidar
}  // namespace plucker
