#include "plucker/lidar/voxel_map.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace plucker {
namespace lidar {
namespace {

constexpr int kMaxPointsPerVoxel = 10000;
constexpr std::size_t kBlockBytes = 256 * 1024;

// log2 of the slots per pool block: the largest power of two whose slots fit in kBlockBytes.
int BlockShift(std::size_t capacity) {
  const std::size_t slots = std::max<std::size_t>(1, kBlockBytes / (capacity * sizeof(float) * 3));
  int shift = 0;
  while ((std::size_t{2} << shift) <= slots) ++shift;
  return shift;
}

const VoxelMapOptions& Validated(const VoxelMapOptions& o) {
  if (!(o.voxel_size > 0.0) || !std::isfinite(o.voxel_size))
    throw std::invalid_argument("voxel map: voxel_size must be > 0, got " +
                                std::to_string(o.voxel_size));
  if (o.max_points_per_voxel < 1 || o.max_points_per_voxel > kMaxPointsPerVoxel)
    throw std::invalid_argument("voxel map: max_points_per_voxel must be in 1.." +
                                std::to_string(kMaxPointsPerVoxel) + ", got " +
                                std::to_string(o.max_points_per_voxel));
  return o;
}

// The 27 offsets d in {-1, 0, 1}^3 by their bit in a neighbour mask, (dx + 1) * 9 + (dy + 1) * 3 +
// dz + 1 (bit 13: the voxel itself; the opposite offset -d has bit 26 - bit): the packed offset
// and d + 1 per axis (indices into per-axis tables).
struct Neighbour {
  std::uint64_t packed;
  int x, y, z;
};
constexpr std::array<Neighbour, 27> kNeighbours = [] {
  std::array<Neighbour, 27> table{};
  for (int b = 0; b < 27; ++b)
    table[b] = {PackedOffset(b / 9 - 1, b / 3 % 3 - 1, b % 3 - 1), b / 9, b / 3 % 3, b % 3};
  return table;
}();
constexpr std::uint32_t kAllNeighbours = ((std::uint32_t{1} << 27) - 1) & ~(1u << 13);

}  // namespace

VoxelMap::VoxelMap(const VoxelMapOptions& options)
    : options_(Validated(options)),
      inv_size_(1.0 / options.voxel_size),
      capacity_(static_cast<std::size_t>(options.max_points_per_voxel)),
      block_shift_(BlockShift(capacity_)),
      block_mask_((std::uint32_t{1} << block_shift_) - 1) {}

std::uint32_t VoxelMap::NewSlot() {
  if (!free_slots_.empty()) {
    const std::uint32_t slot = free_slots_.back();
    free_slots_.pop_back();
    return slot;
  }
  if ((num_slots_ >> block_shift_) >= blocks_.size()) {
    blocks_.emplace_back(new Eigen::Vector3f[capacity_ << block_shift_]);
    neighbour_mask_.resize(blocks_.size() << block_shift_);
  }
  return num_slots_++;
}

std::uint32_t VoxelMap::LinkNeighbours(std::uint64_t key) {
  std::uint32_t mask = 0;
  for (int bit = 0; bit < 27; ++bit) {
    if (bit == 13) continue;
    const auto it = voxels_.find(key + kNeighbours[bit].packed);
    if (it == voxels_.end()) continue;
    mask |= 1u << bit;
    neighbour_mask_[it->second.slot] |= 1u << (26 - bit);  // the new voxel is its opposite
  }
  return mask;
}

int VoxelMap::AddPoints(const std::vector<Eigen::Vector3d>& points_w) {
  const float min_sq =
      static_cast<float>(options_.min_point_distance * options_.min_point_distance);
  int added = 0;
  for (const Eigen::Vector3d& p : points_w) {
    if (!p.allFinite()) continue;
    const std::uint64_t key = PackVoxel(VoxelOf(p, inv_size_));
    auto it = voxels_.find(key);
    if (it == voxels_.end()) {
      const std::uint32_t slot = NewSlot();
      neighbour_mask_[slot] = LinkNeighbours(key);
      it = voxels_.emplace(key, Voxel{slot, 0}).first;
    }
    Voxel& voxel = it.value();
    if (voxel.count >= capacity_) continue;
    Eigen::Vector3f* stored = SlotPoints(voxel.slot);
    const Eigen::Vector3f pf = p.cast<float>();
    std::uint32_t i = 0;
    while (i < voxel.count && (stored[i] - pf).squaredNorm() >= min_sq) ++i;
    if (i < voxel.count) continue;  // closer than min_point_distance to a stored point
    stored[voxel.count++] = pf;
    ++num_points_;
    ++added;
  }
  return added;
}

void VoxelMap::RemoveFar(const Eigen::Vector3d& origin_w) {
  const double max_sq = options_.max_distance * options_.max_distance;
  for (auto it = voxels_.begin(); it != voxels_.end();) {
    const Eigen::Vector3d centre_w =
        (UnpackVoxel(it->first).cast<double>().array() + 0.5) * options_.voxel_size;
    if ((centre_w - origin_w).squaredNorm() <= max_sq) {
      ++it;
      continue;
    }
    num_points_ -= it->second.count;
    free_slots_.push_back(it->second.slot);
    it = voxels_.erase(it);
  }
}

int VoxelMap::KNearest(const Eigen::Vector3d& query_w, int k, double max_distance,
                       std::vector<Eigen::Vector3d>* neighbours, float* reach) const {
  constexpr int kMaxK = 16;
  k = std::min(k, kMaxK);
  std::array<float, kMaxK> best_d;
  std::array<Eigen::Vector3f, kMaxK> best_p;
  int count = 0;
  float worst = static_cast<float>(max_distance * max_distance);
  const Eigen::Vector3f q = query_w.cast<float>();
  const Eigen::Vector3i c = VoxelOf(query_w, inv_size_);
  const Eigen::Vector3d local = query_w * inv_size_ - c.cast<double>();
  const double size_sq = options_.voxel_size * options_.voxel_size;
  // Squared distance to the nearest point not returned (`local`: the query inside its voxel).
  const double margin = std::min(local.minCoeff(), 1.0 - local.maxCoeff()) + 1.0;
  float beyond = static_cast<float>(margin * margin * size_sq);
  // The query's voxel first; then those of its neighbours in its mask (all 26 when it is absent)
  // nearer than the k-th point found so far, all looked up (points prefetched) before any is
  // scanned, so that the cache misses overlap, then scanned in that order, skipping those that
  // the scans before made farther than `worst`. A neighbour not in the mask holds no point, so it
  // does not bound `beyond` either.
  struct Near {
    const Eigen::Vector3f* points;
    std::uint32_t count;
    float gap_sq;  // from the query to the voxel's box
  };
  std::array<Near, 27> near;
  int num_near = 0;
  // Per axis, the squared gap (voxel units) to the neighbour below, the same voxel and above.
  std::array<std::array<double, 3>, 3> gap;
  for (int a = 0; a < 3; ++a)
    gap[a] = {local(a) * local(a), 0.0, (1.0 - local(a)) * (1.0 - local(a))};
  const std::uint64_t key = PackVoxel(c);  // a neighbour's: key + PackedOffset
  std::uint32_t present = kAllNeighbours;  // neighbours that may hold points
  auto look_up = [&](int bit) {
    const Neighbour& d = kNeighbours[bit];
    const double sq = gap[0][d.x] + gap[1][d.y] + gap[2][d.z];
    const float gap_sq = static_cast<float>(sq * size_sq);
    if (gap_sq > worst) return void(beyond = std::min(beyond, gap_sq));
    const auto it = voxels_.find(key + d.packed);
    if (it == voxels_.end()) return;
    near[num_near] = {SlotPoints(it->second.slot), it->second.count, gap_sq};
    __builtin_prefetch(near[num_near++].points);
  };
  auto scan = [&](const Near& voxel) {
    if (voxel.gap_sq > worst) return void(beyond = std::min(beyond, voxel.gap_sq));
    for (std::uint32_t i = 0; i < voxel.count; ++i) {
      const Eigen::Vector3f& p = voxel.points[i];
      const float d = (p - q).squaredNorm();
      if (d > worst) {
        beyond = std::min(beyond, d);
        continue;
      }
      if (count == k) beyond = std::min(beyond, best_d[k - 1]);
      int j = count < k ? count++ : k - 1;  // insertion into the sorted list
      while (j > 0 && best_d[j - 1] > d) {
        best_d[j] = best_d[j - 1];
        best_p[j] = best_p[j - 1];
        --j;
      }
      best_d[j] = d;
      best_p[j] = p;
      if (count == k) worst = best_d[k - 1];
    }
  };
  if (const auto it = voxels_.find(key); it != voxels_.end()) {
    present = neighbour_mask_[it->second.slot];
    scan({SlotPoints(it->second.slot), it->second.count, 0.0f});
  }
  for (std::uint32_t m = present; m != 0; m &= m - 1) look_up(__builtin_ctz(m));
  for (int v = 0; v < num_near; ++v) scan(near[v]);
  neighbours->resize(count);
  for (int i = 0; i < count; ++i) (*neighbours)[i] = best_p[i].cast<double>();
  if (reach) *reach = std::sqrt(beyond);
  return count;
}

void VoxelMap::Clear() {
  voxels_.clear();
  free_slots_.clear();
  num_slots_ = 0;  // the blocks stay allocated and are refilled from slot 0
  num_points_ = 0;
}

std::vector<Eigen::Vector3d> VoxelMap::Points() const {
  std::vector<Eigen::Vector3d> out;
  out.reserve(num_points_);
  for (const auto& kv : voxels_) {
    const Eigen::Vector3f* stored = SlotPoints(kv.second.slot);
    for (std::uint32_t i = 0; i < kv.second.count; ++i) out.push_back(stored[i].cast<double>());
  }
  return out;
}

}  // namespace lidar
}  // namespace plucker
