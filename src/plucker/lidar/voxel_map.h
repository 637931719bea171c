// Bounded local map for scan-to-map registration: a voxel hash (tsl::robin_map) of cubic voxels,
// each holding at most `max_points_per_voxel` points at least `min_point_distance` apart. Voxels
// farther than `max_distance` from the sensor are dropped by RemoveFar() (memory bounded by the
// kept region). KNearest scans the query's voxel and those of its 26 neighbours that hold points
// (a mask per voxel; max_distance <= voxel_size). Storage does not churn the heap (a std::vector
// per voxel fragmented it on long drives): each voxel owns a slot of 12-byte points in a pool of
// ~256 KB blocks that only grows; new voxels reuse the slots of removed ones.
#pragma once

#include <tsl/robin_map.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

namespace plucker {
namespace lidar {

// Integer voxel coordinates packed into one 64-bit hash key.
// 21 bits per axis (offset binary): +-2^20 voxels per axis, e.g. +-1048 km at 1 m voxels.
constexpr std::int64_t kVoxelOffset = std::int64_t{1} << 20;
constexpr std::uint64_t kVoxelMask = (std::uint64_t{1} << 21) - 1;
inline std::uint64_t PackVoxel(const Eigen::Vector3i& v) {
  auto axis = [](int c) { return static_cast<std::uint64_t>(c + kVoxelOffset) & kVoxelMask; };
  return (axis(v.x()) << 42) | (axis(v.y()) << 21) | axis(v.z());
}
inline Eigen::Vector3i UnpackVoxel(std::uint64_t key) {
  auto axis = [&](int shift) {
    return static_cast<int>(static_cast<std::int64_t>((key >> shift) & kVoxelMask) - kVoxelOffset);
  };
  return Eigen::Vector3i(axis(42), axis(21), axis(0));
}

// The packed form of an offset d in {-1, 0, 1}^3: PackVoxel(v + d) = PackVoxel(v) + PackedOffset(d)
// for v within VoxelOf's clamp (each field keeps room for +-1: no carry or borrow between them).
constexpr std::uint64_t PackedOffset(int dx, int dy, int dz) {
  return static_cast<std::uint64_t>(dx * (std::int64_t{1} << 42) + dy * (std::int64_t{1} << 21) +
                                    dz);
}

// Voxel coordinates, clamped to the packable range (no overflow for absurd inputs).
inline Eigen::Vector3i VoxelOf(const Eigen::Vector3d& p, double inv_size) {
  constexpr double kLimit = 1048000.0;
  auto cell = [&](double v) {  // floor by truncation (std::floor: a call without SSE4.1)
    const double c = std::clamp(v * inv_size, -kLimit, kLimit);
    return static_cast<int>(c) - (c < static_cast<int>(c));
  };
  return Eigen::Vector3i(cell(p.x()), cell(p.y()), cell(p.z()));
}

// Hash of a packed key that keeps the 64 voxels of a 4x4x4 block together: a mixing hash of the
// block above the position in the block (6 bits), so that the voxels near a query share a few
// cache lines of the table (robin_map's std::hash<uint64_t> is the identity).
struct VoxelKeyHash {
  std::size_t operator()(std::uint64_t k) const {
    const std::uint64_t in_block = (k >> 38 & 48) | (k >> 19 & 12) | (k & 3);
    k &= ~((3ULL << 42) | (3ULL << 21) | 3ULL);  // the block: 2 low bits per axis cleared
    k = (k ^ k >> 33) * 0xff51afd7ed558ccdULL;
    return static_cast<std::size_t>((k ^ k >> 33) << 6 | in_block);
  }
};

struct VoxelMapOptions {
  double voxel_size = 1.0;          // m; also the largest neighbour search radius
  int max_points_per_voxel = 20;    // cap per voxel (1..10000)
  double min_point_distance = 0.2;  // m; a new point closer than this to a stored one is skipped
  double max_distance = 100.0;      // m; voxels farther from the sensor are removed
};

class VoxelMap {
 public:
  // Throws std::invalid_argument for voxel_size <= 0 or max_points_per_voxel outside 1..10000.
  explicit VoxelMap(const VoxelMapOptions& options = VoxelMapOptions());

  // Adds world points (non-finite ones are ignored). Returns the number actually stored.
  int AddPoints(const std::vector<Eigen::Vector3d>& points_w);
  // Drops every voxel whose centre is farther than max_distance from `origin_w`.
  void RemoveFar(const Eigen::Vector3d& origin_w);

  // Up to k nearest stored points within max_distance (<= voxel_size) of `query_w`, sorted by
  // distance. Returns how many were written into `neighbours` (resized to the count). `reach`:
  // a lower bound of the distance from query_w to every stored point not returned.
  int KNearest(const Eigen::Vector3d& query_w, int k, double max_distance,
               std::vector<Eigen::Vector3d>* neighbours, float* reach = nullptr) const;

  std::size_t NumPoints() const { return num_points_; }
  std::size_t NumVoxels() const { return voxels_.size(); }
  std::size_t NumSlots() const { return num_slots_; }  // slots ever made (pool size)
  bool empty() const { return num_points_ == 0; }
  void Clear();  // keeps the pool for reuse
  std::vector<Eigen::Vector3d> Points() const;
  const VoxelMapOptions& options() const { return options_; }

 private:
  struct Voxel {
    std::uint32_t slot;   // index into the pool
    std::uint32_t count;  // points stored, <= capacity_
  };
  std::uint32_t NewSlot();
  // Sets the bit of the new voxel `key` in its neighbours' masks; returns the mask of its
  // neighbours present.
  std::uint32_t LinkNeighbours(std::uint64_t key);
  Eigen::Vector3f* SlotPoints(std::uint32_t slot) const {
    return blocks_[slot >> block_shift_].get() + (slot & block_mask_) * capacity_;
  }

  VoxelMapOptions options_;
  double inv_size_;
  std::size_t capacity_;  // points per slot (max_points_per_voxel)
  int block_shift_;       // slots per block = 2^block_shift_
  std::uint32_t block_mask_;
  tsl::robin_map<std::uint64_t, Voxel, VoxelKeyHash> voxels_;
  std::vector<std::unique_ptr<Eigen::Vector3f[]>> blocks_;
  std::vector<std::uint32_t> free_slots_;  // slots of removed voxels
  // Per slot, a bit per neighbour that may hold points (set when either voxel is made; left set
  // when the neighbour is removed, which costs KNearest a failed lookup and RemoveFar nothing).
  // KNearest looks up only these.
  std::vector<std::uint32_t> neighbour_mask_;
  std::uint32_t num_slots_ = 0;
  std::size_t num_points_ = 0;
};

}  // namespace lidar
}  // namespace plucker
