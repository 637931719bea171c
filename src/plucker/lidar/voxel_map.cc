#include "plucker/lidar/voxel_map.h"

#include <algorithm>
#include <array>
#include <limits>

namespace plucker {
namespace lidar {

VoxelMap::VoxelMap(const VoxelMapOptions& options)
    : options_(options), inv_size_(1.0 / options.voxel_size) {}

int VoxelMap::AddPoints(const std::vector<Eigen::Vector3d>& points_w) {
  const float min_sq =
      static_cast<float>(options_.min_point_distance * options_.min_point_distance);
  const std::size_t cap = static_cast<std::size_t>(std::max(1, options_.max_points_per_voxel));
  int added = 0;
  for (const Eigen::Vector3d& p : points_w) {
    if (!p.allFinite()) continue;
    const std::uint64_t key = PackVoxel(VoxelOf(p, inv_size_));
    auto it = voxels_.find(key);
    if (it == voxels_.end()) {
      it = voxels_.emplace(key, Voxel()).first;
      it.value().points.reserve(std::min<std::size_t>(cap, 8));
    }
    std::vector<Eigen::Vector3f>& stored = it.value().points;
    if (stored.size() >= cap) continue;
    const Eigen::Vector3f pf = p.cast<float>();
    bool close = false;
    for (const Eigen::Vector3f& q : stored) {
      if ((q - pf).squaredNorm() < min_sq) {
        close = true;
        break;
      }
    }
    if (close) continue;
    stored.push_back(pf);
    ++num_points_;
    ++added;
  }
  return added;
}

void VoxelMap::RemoveFar(const Eigen::Vector3d& origin_w) {
  const double max_sq = options_.max_distance * options_.max_distance;
  constexpr std::int64_t kOffset = std::int64_t{1} << 20;
  constexpr std::uint64_t kMask = (std::uint64_t{1} << 21) - 1;
  for (auto it = voxels_.begin(); it != voxels_.end();) {
    const std::uint64_t key = it->first;
    const Eigen::Vector3d centre(
        (static_cast<double>(static_cast<std::int64_t>((key >> 42) & kMask) - kOffset) + 0.5),
        (static_cast<double>(static_cast<std::int64_t>((key >> 21) & kMask) - kOffset) + 0.5),
        (static_cast<double>(static_cast<std::int64_t>(key & kMask) - kOffset) + 0.5));
    if ((centre * options_.voxel_size - origin_w).squaredNorm() > max_sq) {
      num_points_ -= it->second.points.size();
      it = voxels_.erase(it);
    } else {
      ++it;
    }
  }
}

int VoxelMap::KNearest(const Eigen::Vector3d& query_w, int k, double max_distance,
                       std::vector<Eigen::Vector3d>* neighbours) const {
  constexpr int kMaxK = 16;
  k = std::min(k, kMaxK);
  std::array<float, kMaxK> best_d;
  std::array<Eigen::Vector3f, kMaxK> best_p;
  int count = 0;
  float worst = static_cast<float>(max_distance * max_distance);
  const Eigen::Vector3f q = query_w.cast<float>();
  const Eigen::Vector3i c = VoxelOf(query_w, inv_size_);
  // Offsets of the query inside its voxel, to bound the distance to each neighbouring voxel.
  const Eigen::Vector3d local = query_w * inv_size_ - c.cast<double>();
  const double size_sq = options_.voxel_size * options_.voxel_size;
  auto scan_voxel = [&](const Eigen::Vector3i& offset) {
    // Squared distance from the query to the voxel's box (in voxel units, then metres).
    double gap_sq = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double g = offset(a) < 0 ? local(a) : (offset(a) > 0 ? 1.0 - local(a) : 0.0);
      gap_sq += g * g;
    }
    if (gap_sq * size_sq > worst) return;
    const auto it = voxels_.find(PackVoxel(c + offset));
    if (it == voxels_.end()) return;
    for (const Eigen::Vector3f& p : it->second.points) {
      const float d = (p - q).squaredNorm();
      if (d > worst) continue;
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
  scan_voxel(Eigen::Vector3i::Zero());  // the query's own voxel first: it tightens `worst`
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz)
        if (dx || dy || dz) scan_voxel(Eigen::Vector3i(dx, dy, dz));
  neighbours->resize(count);
  for (int i = 0; i < count; ++i) (*neighbours)[i] = best_p[i].cast<double>();
  return count;
}

void VoxelMap::Clear() {
  voxels_.clear();
  num_points_ = 0;
}

std::vector<Eigen::Vector3d> VoxelMap::Points() const {
  std::vector<Eigen::Vector3d> out;
  out.reserve(num_points_);
  for (const auto& kv : voxels_)
    for (const Eigen::Vector3f& p : kv.second.points) out.push_back(p.cast<double>());
  return out;
}

}  // namespace lidar
}  // namespace plucker
