#include "plucker/lidar/features.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include "plucker/geometry/fast_atan2.h"
#include "plucker/lidar/voxel_map.h"

namespace plucker {
namespace lidar {
namespace {

constexpr int kMaxRings = 1024;
constexpr int kShortList = 8;  // flat candidates kept per sector (SelectRingFeatures)

// One ring's points in firing order as indices into the scan (range-gated and gathered in
// RingScratch, so that the split into rings reads the ring channel only, not the points).
using Ring = std::vector<int>;

// Time of a ring point from the azimuth swept since the ring's first point (its direction).
struct AzimuthClock {
  AzimuthClock(const std::vector<Eigen::Vector3d>& p, double period)
      : period(period), n(p.size()), start(Azimuth(p[0])) {
    direction = Wrap(Azimuth(p[std::max<std::size_t>(1, n / 4)]) - start) >= 0.0 ? 1.0 : -1.0;
  }
  double operator()(const Eigen::Vector3d& p, std::size_t index) const {
    double swept = Wrap(direction * (Azimuth(p) - start));
    if (swept < 0.0) swept += 2.0 * M_PI;
    // Near the end of the ring a sweep slightly past 2 pi wraps to ~0: use the index to tell.
    if (index > n / 2 && swept < 0.5 * M_PI) swept = 2.0 * M_PI;
    if (index < n / 2 && swept > 1.5 * M_PI) swept = 0.0;
    return period * swept / (2.0 * M_PI);
  }
  static double Azimuth(const Eigen::Vector3d& p) { return FastAtan2(p.y(), p.x()); }
  static double Wrap(double a) { return std::remainder(a, 2.0 * M_PI); }
  double period;
  std::size_t n;
  double start, direction = 1.0;
};

// The features of one ring (its valid points in firing order).
struct RingFeatures {
  std::vector<Eigen::Vector3d> sharp, flat, edges, planes;
  std::vector<double> edge_times, plane_times;
  int valid = 0;  // points that passed the range gate (finite, min_range..max_range)
  int occluded_rejected = 0, parallel_rejected = 0;
  bool used = false;  // enough points for the curvature window and the sectors

  void Clear() {  // keeps the capacity
    for (auto* v : {&sharp, &flat, &edges, &planes}) v->clear();
    edge_times.clear(), plane_times.clear(), used = false;
    valid = occluded_rejected = parallel_rejected = 0;
  }
};

// Per-ring working arrays, reused from ring to ring and scan to scan.
struct RingScratch {
  std::vector<Eigen::Vector3d> p, prefix;  // the ring's valid points (gathered), prefix sums
  std::vector<int> index;                  // their indices into the scan
  std::vector<double> depth_sq, curvature;
  std::vector<char> picked, label;
  std::vector<std::pair<double, int>> order;  // edge candidates: curvature, index
};

void SelectRingFeatures(const Ring& ring, const LidarScan& scan, const FeatureOptions& o,
                        RingScratch* scratch, RingFeatures* out) {
  out->Clear();
  // The valid points (finite, within the range gate), gathered without a branch per point.
  std::vector<Eigen::Vector3d>& p = scratch->p;
  std::vector<double>& depth_sq = scratch->depth_sq;  // squared: no square root per point
  std::vector<int>& index = scratch->index;
  p.resize(ring.size()), depth_sq.resize(ring.size()), index.resize(ring.size());
  const double min_sq = o.min_range * o.min_range, max_sq = o.max_range * o.max_range;
  int n = 0;
  for (const int j : ring) {
    const Eigen::Vector3d q = scan.points[j];  // a local: the count does not wait for the store
    const double range_sq = q.squaredNorm();
    p[n] = q, depth_sq[n] = range_sq, index[n] = j;
    n += q.allFinite() & (range_sq >= min_sq) & (range_sq <= max_sq);
  }
  p.resize(n);
  out->valid = n;
  const int k = std::max(1, o.curvature_half_window);
  if (n < 2 * k + 1 + o.sectors) return;
  out->used = true;
  const bool has_time = !scan.time.empty();
  const bool times = o.compute_times;
  const double supp_sq = o.suppression_distance * o.suppression_distance;
  const double thin_sq = 0.25 * o.plane_voxel_size * o.plane_voxel_size;
  const double edge_threshold = o.edge_threshold;  // a local: `order` stores do not alias it
  const AzimuthClock clock(p, o.scan_period);
  auto time_of = [&](int i) {
    return has_time ? scan.time[index[i]] : clock(p[i], static_cast<std::size_t>(i));
  };

  // Curvature with a prefix sum: sum_{j!=0} (p_{i+j} - p_i) = S(i-k..i+k) - (2k+1) p_i.
  std::vector<Eigen::Vector3d>& prefix = scratch->prefix;
  prefix.resize(n + 1);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();  // a local: no store-to-load chain per point
  prefix[0] = sum;
  for (int i = 0; i < n; ++i) prefix[i + 1] = sum += p[i];
  std::vector<double>& curvature = scratch->curvature;
  curvature.resize(n);  // the k points at each end have no full window: curvature 0
  std::fill(curvature.begin(), curvature.begin() + k, 0.0);
  std::fill(curvature.end() - k, curvature.end(), 0.0);
  for (int i = k; i < n - k; ++i) {
    const Eigen::Vector3d diff = (prefix[i + k + 1] - prefix[i - k]) - (2 * k + 1) * p[i];
    curvature[i] = diff.squaredNorm();
  }

  // Unreliable points (LOAM): occlusion boundaries and surfaces parallel to the beam.
  std::vector<char>& picked = scratch->picked;
  std::vector<char>& label = scratch->label;
  picked.assign(n, 0), label.assign(n, 0);
  // A relative depth jump |d1 - d2| > t min(d1, d2) is max(d1, d2) > (1 + t) min(d1, d2): tested
  // on the squared depths, so that only the few jumps take square roots (t <= -1: every pair).
  const double jump = std::max(0.0, 1.0 + o.occlusion_depth_jump), jump_sq = jump * jump;
  const double parallel_beam_ratio = o.parallel_beam_ratio;  // a local: not reloaded per point
  double prev_sq = (p[k] - p[k - 1]).squaredNorm();          // |p_i - p_{i-1}|^2, carried along
  for (int i = k; i < n - k - 1; ++i) {
    const double s1 = depth_sq[i], s2 = depth_sq[i + 1];
    if (std::max(s1, s2) > jump_sq * std::min(s1, s2)) {
      const double d1 = std::sqrt(s1), d2 = std::sqrt(s2);
      // Only between angularly adjacent points: the k points on the farther surface next to the
      // jump may be occluded.
      if ((p[i + 1] / d2 - p[i] / d1).norm() < o.occlusion_max_gap / std::min(d1, d2)) {
        for (int j = d1 > d2 ? i - k + 1 : i + 1, l = 0; l < k; ++j, ++l) {
          if (!picked[j]) ++out->occluded_rejected;
          picked[j] = 2;
        }
      }
    }
    const double next_sq = (p[i + 1] - p[i]).squaredNorm();
    const double bound = parallel_beam_ratio * s1;
    if (prev_sq > bound && next_sq > bound && !picked[i]) {
      picked[i] = 2;
      ++out->parallel_rejected;
    }
    prev_sq = next_sq;
  }

  auto suppress = [&](int i) {
    for (int l = 1; l <= k && i + l < n; ++l) {
      if ((p[i + l] - p[i + l - 1]).squaredNorm() > supp_sq) break;
      if (!picked[i + l]) picked[i + l] = 1;
    }
    for (int l = 1; l <= k && i - l >= 0; ++l) {
      if ((p[i - l] - p[i - l + 1]).squaredNorm() > supp_sq) break;
      if (!picked[i - l]) picked[i - l] = 1;
    }
  };

  auto& order = scratch->order;
  const int usable = n - 2 * k;
  for (int s = 0; s < o.sectors; ++s) {
    const int begin = k + usable * s / o.sectors;
    const int end = k + usable * (s + 1) / o.sectors;  // exclusive
    if (end <= begin) continue;
    // Edge candidates (curvature above the threshold, usually few), strongest first; gathered
    // without branches, sorted with their curvatures beside them (no lookups in the comparisons).
    // `order` only grows: shrinking and regrowing it zeroed ~2 MB per scan.
    if (order.size() < static_cast<std::size_t>(end - begin)) order.resize(end - begin);
    int candidates = 0;
    for (int i = begin; i < end; ++i) {
      order[candidates] = {curvature[i], i};
      candidates += (curvature[i] > edge_threshold) & (picked[i] == 0);
    }
    std::sort(order.begin(), order.begin() + candidates,
              [](const auto& a, const auto& b) { return a.first > b.first; });
    int count = 0;
    for (auto it = order.begin(); it != order.begin() + candidates; ++it) {
      const int i = it->second;
      if (picked[i]) continue;
      ++count;
      if (count > o.max_edges_per_sector) break;
      if (count <= o.max_sharp_per_sector) out->sharp.push_back(p[i]);
      label[i] = 1;
      out->edges.push_back(p[i]);
      if (times) out->edge_times.push_back(time_of(i));
      picked[i] = 1;
      suppress(i);
    }

    // Flat: the smallest curvatures below plane_threshold (first of equal minima first): the first
    // unsuppressed of the kShortList smallest, kept by one pass (again if all are suppressed).
    std::array<int, kShortList> list;
    int size = kShortList, next = kShortList;  // all used up: filled for the first pick
    auto fill = [&] {
      size = next = 0;
      double bound = o.plane_threshold;  // a candidate is below (full list: below its last)
      for (int i = begin; i < end; ++i) {
        const double c = curvature[i];
        if ((c >= bound) | (picked[i] != 0)) continue;  // one branch, mostly taken
        int j = size < kShortList ? size++ : size - 1;
        for (; j > 0 && c < curvature[list[j - 1]]; --j) list[j] = list[j - 1];
        list[j] = i;
        if (size == kShortList) bound = curvature[list[size - 1]];
      }
    };
    for (count = 0; count < o.max_flat_per_sector; ++count) {
      while (next < size && picked[list[next]]) ++next;
      if (next == size && size == kShortList) fill();
      if (next == size) break;
      const int best = list[next];
      label[best] = -1;
      out->flat.push_back(p[best]);
      picked[best] = 1;
      suppress(best);
    }

    // Less flat: every non-edge point that was not rejected, thinned along the ring first.
    Eigen::Vector3d last(1e30, 1e30, 1e30);
    for (int i = begin; i < end; ++i) {
      if ((label[i] > 0) | (picked[i] == 2)) continue;
      if ((label[i] == 0) & ((p[i] - last).squaredNorm() < thin_sq)) continue;
      last = p[i];
      out->planes.push_back(p[i]);
      if (times) out->plane_times.push_back(time_of(i));
    }
  }
}

template <typename T>
void Append(const std::vector<T>& from, std::vector<T>* to) {
  to->insert(to->end(), from.begin(), from.end());
}

// The voxel keys seen by a downsampling: open addressing with linear probing in a power-of-two
// table of bare keys (8 bytes a slot; empty = ~0, which PackVoxel's 63 bits never give), at most
// half full, grown by doubling and kept from call to call, cleared by one fill. (tsl::robin_set
// spends a fifth of the downsampling clearing its 16-byte buckets one by one.)
class VoxelKeySet {
 public:
  void Clear() { std::fill(slots_.begin(), slots_.end(), kEmpty), size_ = 0; }
  bool Insert(std::uint64_t key) {  // true when the key is new
    if (2 * (size_ + 1) > slots_.size()) Grow();
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = Slot(key);; i = (i + 1) & mask) {
      if (slots_[i] == key) return false;
      if (slots_[i] == kEmpty) return slots_[i] = key, ++size_, true;
    }
  }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
  std::size_t Slot(std::uint64_t key) const {  // Fibonacci hashing: the top bits of key * 2^64/phi
    return static_cast<std::size_t>((key * 0x9e3779b97f4a7c15ULL) >> shift_);
  }
  void Grow() {
    std::vector<std::uint64_t> old(std::max<std::size_t>(1024, 2 * slots_.size()), kEmpty);
    old.swap(slots_);
    shift_ = 64 - __builtin_ctzll(slots_.size());
    size_ = 0;
    for (const std::uint64_t key : old)
      if (key != kEmpty) Insert(key);
  }
  std::vector<std::uint64_t> slots_;
  std::size_t size_ = 0;
  int shift_ = 64;
};

// VoxelDownsample with a caller-owned set of the voxel keys seen (reused from call to call).
void VoxelDownsampleWith(double voxel_size, std::vector<Eigen::Vector3d>* points,
                         std::vector<double>* times, VoxelKeySet* seen) {
  if (voxel_size <= 0.0 || points->empty()) return;
  const bool with_times = times != nullptr && times->size() == points->size();
  const double inv = 1.0 / voxel_size;
  seen->Clear();  // keeps its table: sized by the distinct voxels seen (cache-friendly)
  std::size_t out = 0;
  std::uint64_t last = ~std::uint64_t{0};  // the previous point's voxel (already in `seen`)
  for (std::size_t i = 0; i < points->size(); ++i) {
    const std::uint64_t key = PackVoxel(VoxelOf((*points)[i], inv));
    if (key == last || !seen->Insert(last = key)) continue;
    (*points)[out] = (*points)[i];
    if (with_times) (*times)[out] = (*times)[i];
    ++out;
  }
  points->resize(out);
  if (with_times) times->resize(out);
}

}  // namespace

void VoxelDownsample(double voxel_size, std::vector<Eigen::Vector3d>* points,
                     std::vector<double>* times) {
  VoxelKeySet seen;
  VoxelDownsampleWith(voxel_size, points, times, &seen);
}

struct FeatureExtractor::Buffers {
  std::vector<Ring> rings;
  std::vector<RingFeatures> per_ring;
  RingScratch scratch;                                          // one thread
  tbb::enumerable_thread_specific<RingScratch> thread_scratch;  // several
  VoxelKeySet seen;
};

FeatureExtractor::FeatureExtractor() : buffers_(std::make_unique<Buffers>()) {}
FeatureExtractor::~FeatureExtractor() = default;

bool FeatureExtractor::Extract(const LidarScan& scan, const FeatureOptions& o,
                               ScanFeatures* features, std::string* error) {
  for (auto* v : {&features->sharp, &features->edges, &features->flat, &features->planes})
    v->clear();
  features->edge_times.clear(), features->plane_times.clear();
  features->stats = FeatureStats();
  FeatureStats& stats = features->stats;
  stats.input_points = static_cast<int>(scan.size());
  if (scan.ring.size() != scan.size()) {
    *error = "scan has no ring channel (assign rings first)";
    return false;
  }
  const bool has_time = !scan.time.empty();
  if (has_time && scan.time.size() != scan.size()) {
    *error = "time channel size differs from the point count";
    return false;
  }

  // Split into rings, keeping firing order (range gating and NaN removal come with the gather).
  std::vector<Ring>& rings = buffers_->rings;
  rings.resize(kMaxRings);  // allocated once, cleared keeping their capacity
  for (Ring& ring : rings) ring.clear();
  int num_rings = 0;  // 1 + the highest ring with a point
  // Runs of equal ring (a firing-order scan is a run per ring) are appended at once.
  for (std::size_t i = 0, end = i; i < scan.size(); i = end) {
    const int r = scan.ring[i];
    if (r >= kMaxRings) {
      *error = "ring index " + std::to_string(r) + " out of range";
      return false;
    }
    while (end < scan.size() && scan.ring[end] == r) ++end;
    if (r < 0) continue;
    Ring& ring = rings[r];
    const std::size_t before = ring.size();
    ring.resize(before + (end - i));
    std::iota(ring.begin() + before, ring.end(), static_cast<int>(i));
    num_rings = std::max(num_rings, r + 1);
  }

  const bool times = o.compute_times;
  stats.times_from_azimuth = times && !has_time;
  // Rings are independent: in parallel when asked, concatenated in ring order (same result).
  std::vector<RingFeatures>& per_ring = buffers_->per_ring;
  if (static_cast<int>(per_ring.size()) < num_rings) per_ring.resize(num_rings);
  if (o.num_threads > 1) {
    tbb::task_arena arena(o.num_threads);
    arena.execute([&] {
      tbb::parallel_for(0, num_rings, [&](int r) {
        SelectRingFeatures(rings[r], scan, o, &buffers_->thread_scratch.local(), &per_ring[r]);
      });
    });
  } else {
    for (int r = 0; r < num_rings; ++r)
      SelectRingFeatures(rings[r], scan, o, &buffers_->scratch, &per_ring[r]);
  }
  for (int r = 0; r < num_rings; ++r) {
    const RingFeatures& f = per_ring[r];
    stats.valid_points += f.valid;
    if (!f.used) continue;
    ++stats.rings;
    stats.occluded_rejected += f.occluded_rejected;
    stats.parallel_rejected += f.parallel_rejected;
    Append(f.sharp, &features->sharp);
    Append(f.flat, &features->flat);
    Append(f.edges, &features->edges);
    Append(f.planes, &features->planes);
    Append(f.edge_times, &features->edge_times);
    Append(f.plane_times, &features->plane_times);
  }
  if (stats.rings == 0) {
    *error = "no ring has enough valid points (" + std::to_string(stats.valid_points) +
             " valid of " + std::to_string(stats.input_points) + ")";
    return false;
  }
  VoxelDownsampleWith(o.edge_voxel_size, &features->edges, times ? &features->edge_times : nullptr,
                      &buffers_->seen);
  VoxelDownsampleWith(o.plane_voxel_size, &features->planes,
                      times ? &features->plane_times : nullptr, &buffers_->seen);
  stats.sharp = static_cast<int>(features->sharp.size());
  stats.edges = static_cast<int>(features->edges.size());
  stats.flat = static_cast<int>(features->flat.size());
  stats.planes = static_cast<int>(features->planes.size());
  return true;
}

}  // namespace lidar
}  // namespace plucker
