// Bounded local map for scan-to-map registration: a voxel hash (tsl::robin_map) of cubic voxels,
// each holding at most `max_points_per_voxel` points that are at least `min_point_distance` apart
// (an incremental voxel downsampling: the map never stores denser than that). Voxels farther
// than `max_distance` from the current sensor position are dropped by RemoveFar(), so memory is
// bounded by the volume of the kept region whatever the sequence length.
//
// Nearest neighbours: the query's voxel and its 26 neighbours are scanned, so every point within
// `voxel_size` of the query is found (KNearest's max_distance must be <= voxel_size).
#pragma once

#include <tsl/robin_map.h>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "plucker/lidar/voxel_key.h"

namespace plucker {
namespace lidar {

struct VoxelMapOptions {
  double voxel_size = 1.0;          // m; also the largest neighbour search radius
  int max_points_per_voxel = 20;    // cap per voxel
  double min_point_distance = 0.2;  // m; a new point closer than this to a stored one is skipped
  double max_distance = 100.0;      // m; voxels farther from the sensor are removed
};

class VoxelMap {
 public:
  explicit VoxelMap(const VoxelMapOptions& options = VoxelMapOptions());

  // Adds world points (non-finite ones are ignored). Returns the number actually stored.
  int AddPoints(const std::vector<Eigen::Vector3d>& points_w);
  // Drops every voxel whose centre is farther than max_distance from `origin_w`.
  void RemoveFar(const Eigen::Vector3d& origin_w);

  // Up to k nearest stored points within max_distance (<= voxel_size) of `query_w`, sorted by
  // distance. Returns how many were written into `neighbours` (resized to the count).
  int KNearest(const Eigen::Vector3d& query_w, int k, double max_distance,
               std::vector<Eigen::Vector3d>* neighbours) const;

  std::size_t NumPoints() const { return num_points_; }
  std::size_t NumVoxels() const { return voxels_.size(); }
  bool empty() const { return num_points_ == 0; }
  void Clear();
  std::vector<Eigen::Vector3d> Points() const;
  const VoxelMapOptions& options() const { return options_; }

 private:
  struct Voxel {
    std::vector<Eigen::Vector3f> points;
  };
  VoxelMapOptions options_;
  double inv_size_;
  tsl::robin_map<std::uint64_t, Voxel, VoxelKeyHash> voxels_;
  std::size_t num_points_ = 0;
};

}  // namespace lidar
}  // namespace plucker
