#include "plucker/lidar/odometry.h"

#include <ceres/loss_function.h>

#include <algorithm>
#include <array>
#include <optional>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "plucker/geometry/fitting.h"
#include "plucker/lidar/deskew.h"
#include "plucker/lidar/pose_solver.h"
#include "plucker/lidar/sweep_motion.h"
#include "plucker/sensor/lidar_model.h"

namespace plucker {
namespace lidar {

namespace {

// A feature point p_s and its map plane (x_w, normal d_w) or line (x_w, direction d_w).
struct Match {
  Eigen::Vector3d p_s, x_w, d_w;
};

// Fits the map plane (all nb within plane_max_residual) or line (elongated covariance) of nb.
bool FitMap(const std::vector<Eigen::Vector3d>& nb, bool plane, const LidarOdometryOptions& o,
            Match* m) {
  m->x_w = Eigen::Vector3d::Zero();
  for (const auto& p : nb) m->x_w += p;
  m->x_w /= static_cast<double>(nb.size());
  // The scatter matrix: n times the covariance, with the same eigenvectors and eigenvalue ratios.
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& p : nb) scatter.noalias() += (p - m->x_w) * (p - m->x_w).transpose();
  const ExtremeEigenpair fit = plane ? SmallestEigenpair(scatter) : LargestEigenpair(scatter);
  m->d_w = fit.vector;
  if (!plane) return fit.value > o.edge_eigen_ratio * fit.middle;
  return std::none_of(nb.begin(), nb.end(), [&](const Eigen::Vector3d& q_w) {
    return std::abs(m->d_w.dot(q_w - m->x_w)) > o.plane_max_residual;
  });
}

// Map points searched per feature point in a scan's first round: the 5 neighbours and one spare,
// which lets the later rounds prove most of their neighbours from the cache (8 searched more of
// the map for few more proofs: docs/lidar-odometry.md, round 8).
constexpr int kCandidates = 6;
constexpr int kMaxNeighbours = 16;

// One feature point's neighbour search, kept over the association rounds of a scan: the k nearest
// map points of the moved query are taken from the candidates found before when provably nearer
// than any other map point (`reach` less the distance moved), else searched again; the fit of an
// unchanged neighbour set is kept. Results equal a fresh search (up to ties).
struct NeighbourCache {
  Eigen::Vector3f q_w;  // query of the last search
  float reach = 0.0f;   // every map point not in `cand` is at least this far from q_w
  int n = 0;            // candidates, nearest first
  std::array<Eigen::Vector3f, kMaxNeighbours> cand;
  unsigned fit_set = 0;  // bit mask of the candidates `match` was fitted to (0: none)
  bool matched = false;  // the fit gave a match
  Match match;
};

// The k nearest map points within max_d of q_w into *nb, nearest first, from the cache when it
// proves them (never after a reset). Returns their bit mask over c->cand.
unsigned Nearest(const VoxelMap& map, const Eigen::Vector3d& q_w, int k, double max_d,
                 NeighbourCache* c, std::vector<Eigen::Vector3d>* nb) {
  const Eigen::Vector3f q = q_w.cast<float>();
  std::array<std::pair<float, int>, kMaxNeighbours> d;
  for (int j = 0; j < c->n; ++j) {  // insertion sort (n <= 16: no heap as in partial_sort)
    const std::pair<float, int> e((c->cand[j] - q).squaredNorm(), j);
    const auto at = std::upper_bound(d.begin(), d.begin() + j, e);
    *std::prev(std::copy_backward(at, d.begin() + j, d.begin() + j + 1)) = e;  // at <- e
  }
  const int m = std::min(k, c->n);
  int count = 0;
  while (count < m && d[count].first <= static_cast<float>(max_d * max_d)) ++count;
  const float bound = count == k ? std::sqrt(d[k - 1].first) : static_cast<float>(max_d);
  if (bound + (q - c->q_w).norm() < c->reach * (1.0f - 1e-5f)) {  // reach 0 after a reset
    unsigned set = 0;
    nb->resize(count);
    for (int j = 0; j < count; ++j) {
      (*nb)[j] = c->cand[d[j].second].cast<double>();
      set |= 1u << d[j].second;
    }
    return set;
  }
  c->n = map.KNearest(q_w, std::max(k, kCandidates), max_d, nb, &c->reach);
  for (int j = 0; j < c->n; ++j) c->cand[j] = (*nb)[j].cast<float>();
  c->q_w = q;
  c->fit_set = 0;
  nb->resize(std::min(k, c->n));
  return (1u << nb->size()) - 1;
}

// Every `stride`-th element (and time, if any) so that at most `cap` remain, in place.
void StrideSample(int cap, std::vector<Eigen::Vector3d>* v, std::vector<double>* times) {
  if (cap <= 0 || static_cast<int>(v->size()) <= cap) return;
  const bool with_times = times->size() == v->size();
  const double stride = static_cast<double>(v->size()) / cap;
  for (int i = 0; i < cap; ++i) {
    const std::size_t j = static_cast<std::size_t>(i * stride);
    (*v)[i] = (*v)[j];
    if (with_times) (*times)[i] = (*times)[j];
  }
  v->resize(cap);
  if (with_times) times->resize(cap);
}

// Deskews the feature points with the motion over the sweep T_s_start_s_end.
void DeskewScanPoints(const SE3d& T_s_start_s_end, double period, ScanFeatures* f) {
  DeskewPoints(T_s_start_s_end, period, f->edge_times, &f->edges);
  DeskewPoints(T_s_start_s_end, period, f->plane_times, &f->planes);
}

// The degeneracy criterion of options o (the information ceiling is in units of plane_sigma^-2).
DegeneracyCriterion CriterionFor(const LidarOdometryOptions& o) {
  DegeneracyCriterion criterion;
  criterion.translation_ratio = o.degeneracy_threshold;
  criterion.rotation_ratio = o.degeneracy_rotation_threshold;
  criterion.max_translation_information =
      o.degeneracy_max_normal_alignment / (o.plane_sigma * o.plane_sigma);
  criterion.max_rotation_information = o.degeneracy_max_rotation_information;
  return criterion;
}

void Notify(const StageObserver& observer, Stage stage) { observer ? observer(stage) : void(); }

// The extractor of a scan: LOAM's per ring, or (sensor generic) local geometry, with per-point
// time after a deskew with the sweep motion T_sweep (sweep_motion.h).
struct Extractors {
  FeatureExtractor* rings = nullptr;
  GeometricFeatureExtractor* geometric = nullptr;  // generic
  SweepFeatureExtractor* sweep = nullptr;          // generic with per-point time
  SE3d T_sweep;
};

// The scan's features capped to max_edge_points / max_plane_points unless `all` (times when
// deskewing).
bool ExtractScanFeatures(const LidarScan& scan, const LidarOdometryOptions& o, bool deskew,
                         bool all, const Extractors& x, ScanFeatures* features,
                         std::string* error) {
  FeatureOptions feature_options = o.features;
  feature_options.compute_times = deskew;
  feature_options.num_threads = o.num_threads;
  const bool ok =
      x.sweep       ? x.sweep->Extract(scan, x.T_sweep, feature_options, o.generic, features, error)
      : x.geometric ? x.geometric->Extract(scan, feature_options, o.generic, features, error)
                    : x.rings->Extract(scan, feature_options, features, error);
  if (!ok) return false;
  if (!o.use_edges) features->edges.clear();
  if (all) return true;
  StrideSample(o.max_edge_points, &features->edges, &features->edge_times);
  StrideSample(o.max_plane_points, &features->planes, &features->plane_times);
  return true;
}

}  // namespace

class LidarOdometry::Impl {
 public:
  explicit Impl(const LidarOdometryOptions& o)
      : loss(factors::MakeLossFunction(o.loss, o.loss_scale)) {
    if (o.num_threads > 1) arena = std::make_unique<tbb::task_arena>(o.num_threads);
    if (o.sensor != "auto") sensor = sensor::LidarModelFromName(o.sensor);
    generic = sensor && !sensor->spinning;
  }

  // matches = the successful match_fn(plane, i), i < n, in order (in parallel: the same result).
  template <typename MatchFn>
  void FindMatches(std::size_t n, bool plane, const MatchFn& match_fn,
                   std::vector<Match>* matches) {
    matches->clear();
    if (!arena) {
      Match m;
      for (std::size_t i = 0; i < n; ++i)
        if (match_fn(plane, i, &neighbours, &m)) matches->push_back(m);
      return;
    }
    constexpr std::size_t kChunk = 256;
    const std::size_t chunks = (n + kChunk - 1) / kChunk;
    std::vector<std::vector<Match>> parts(chunks);
    arena->execute([&] {
      tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
        std::vector<Eigen::Vector3d> nb;
        Match m;
        for (std::size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i)
          if (match_fn(plane, i, &nb, &m)) parts[c].push_back(m);
      });
    });
    for (const auto& part : parts) matches->insert(matches->end(), part.begin(), part.end());
  }

  // Plane and edge correspondences (this->planes, this->edges) at T_w_s: k nearest map points
  // (NeighbourCache, reset in the first round) and their fit (FitMap). Returns how many.
  int FindCorrespondences(const VoxelMap& edge_map, const VoxelMap& plane_map,
                          const ScanFeatures& points_s, const SE3d& T_w_s, bool first_round,
                          const LidarOdometryOptions& o) {
    const int k = std::min(o.num_neighbours, kMaxNeighbours);
    const double max_d = std::min(o.max_correspondence_distance, plane_map.options().voxel_size);
    const Eigen::Matrix3d R_w_s = T_w_s.RotationMatrix();
    const Eigen::Vector3d t_w_s = T_w_s.translation();
    plane_cache.resize(points_s.planes.size()), edge_cache.resize(points_s.edges.size());
    auto match = [&](bool plane, std::size_t i, std::vector<Eigen::Vector3d>* nb, Match* m) {
      NeighbourCache& c = (plane ? plane_cache : edge_cache)[i];
      const Eigen::Vector3d& p_s = (plane ? points_s.planes : points_s.edges)[i];
      const VoxelMap& map = plane ? plane_map : edge_map;
      if (first_round) c.n = 0, c.reach = 0.0f;  // a reset (no 1 MB memset per scan)
      const double d = std::min(max_d, map.options().voxel_size);
      const unsigned set = Nearest(map, R_w_s * p_s + t_w_s, k, d, &c, nb);
      if (static_cast<int>(nb->size()) < k) return false;
      if (set != c.fit_set) c.matched = FitMap(*nb, plane, o, &c.match);
      c.fit_set = set;
      *m = c.match;
      m->p_s = p_s;
      return c.matched;
    };
    FindMatches(points_s.planes.size(), true, match, &planes);
    FindMatches(points_s.edges.size(), false, match, &edges);
    return static_cast<int>(planes.size() + edges.size());
  }

  std::unique_ptr<tbb::task_arena> arena;  // none: one thread
  std::unique_ptr<ceres::LossFunction> loss;
  std::optional<sensor::LidarModel> sensor;
  std::vector<Eigen::Vector3d> neighbours;
  std::vector<Match> planes, edges;
  std::vector<NeighbourCache> plane_cache, edge_cache;  // one per feature point of the scan
  LidarResiduals residuals;
  FeatureExtractor feature_extractor;  // these buffers are kept across scans (no heap churn)
  GeometricFeatureExtractor geometric_extractor;  // --sensor generic
  SweepFeatureExtractor sweep_extractor;          // generic with per-point time
  bool generic = false;
  ScanFeatures features;
  std::vector<Eigen::Vector3d> raw_edges, raw_planes;  // while deskewing: the points as measured
  int frames_since_cleanup = 0;
  int registered_streak = 0;  // consecutive registered frames up to the last one (the first: 1)
  int registered_total = 0;   // registered frames so far (the first scan counts)
  std::size_t seed_slot = 0;  // index in poses_ of the first registered scan
  double stamp = 0.0;         // of the scan being processed

  // Deskewing: the first scan seeds the map raw, kept here (at T_w_s_seed) until the next one.
  std::optional<ScanFeatures> seed;
  SE3d T_w_s_seed;
};

LidarOdometry::LidarOdometry(const LidarOdometryOptions& options)
    : options_(options),
      edge_map_(options.edge_map),
      plane_map_(options.plane_map),
      impl_(std::make_unique<Impl>(options)) {}

LidarOdometry::~LidarOdometry() = default;

SE3d PredictPose(const std::vector<SE3d>& T_w_s, bool constant_velocity) {
  if (T_w_s.empty()) return SE3d();
  const SE3d& T_w_s_prev = T_w_s.back();
  if (T_w_s.size() < 2 || !constant_velocity) return T_w_s_prev;
  const SE3d T_s_prev2_s_prev = T_w_s[T_w_s.size() - 2].Inverse() * T_w_s_prev;
  return T_w_s_prev * T_s_prev2_s_prev;
}

SE3d PredictPoseAt(const std::vector<SE3d>& T_w_s, const std::vector<double>& stamps, double stamp,
                   bool constant_velocity, int* steps) {
  *steps = 1;
  const std::size_t n = T_w_s.size();
  if (n < 2 || !constant_velocity || stamps.size() != n)
    return PredictPose(T_w_s, constant_velocity);
  const double interval = stamps[n - 1] - stamps[n - 2], elapsed = stamp - stamps[n - 1];
  if (!(interval > 0.0 && elapsed > 0.0)) return PredictPose(T_w_s, constant_velocity);
  // The last motion spans m scan periods (after a gap), the coming one `steps` periods.
  const int m = interval > 1.5 * elapsed
                    ? static_cast<int>(std::min(std::round(interval / elapsed), 1000.0))
                    : 1;
  const double period = interval / m;
  if (elapsed > 1.5 * period)
    *steps = static_cast<int>(std::min(std::round(elapsed / period), 1000.0));
  if (m == 1 && *steps == 1) return PredictPose(T_w_s, constant_velocity);
  SE3d T_step = T_w_s[n - 2].Inverse() * T_w_s[n - 1];  // over m periods: its m-th root
  if (m > 1) {  // a constant twist: t_m = sum_k R^k t ~ m R^((m - 1) / 2) t
    const Eigen::Vector3d w = LogSO3(T_step.rotation()) / m;
    T_step = SE3d(ExpSO3<double>(w), ExpSO3<double>(-0.5 * (m - 1) * w) * T_step.translation() / m);
  }
  SE3d T_w_s_pred = T_w_s[n - 1];
  for (int k = 0; k < *steps; ++k) T_w_s_pred = T_w_s_pred * T_step;
  return T_w_s_pred;
}

void UpdateLocalMap(const SE3d& T_w_s, bool remove_far, std::vector<Eigen::Vector3d>* edges,
                    std::vector<Eigen::Vector3d>* planes, VoxelMap* edge_map, VoxelMap* plane_map) {
  const Eigen::Matrix3d R_w_s = T_w_s.RotationMatrix();
  const Eigen::Vector3d t_w_s = T_w_s.translation();
  for (auto& p : *edges) p = R_w_s * p + t_w_s;
  for (auto& p : *planes) p = R_w_s * p + t_w_s;
  edge_map->AddPoints(*edges);
  plane_map->AddPoints(*planes);
  if (!remove_far) return;
  edge_map->RemoveFar(t_w_s);
  plane_map->RemoveFar(t_w_s);
}

FrameResult LidarOdometry::SkipFrame(const std::string& reason, double stamp) {
  FrameResult result;  // ok = false
  result.error = reason;
  impl_->registered_streak = 0;
  int steps = 1;
  result.T_w_s = options_.restart_from_stamps
                     ? PredictPoseAt(poses_, stamps_, stamp, options_.constant_velocity, &steps)
                     : PredictPose(poses_, options_.constant_velocity);
  PredictAfterWideStart(stamp, &result.T_w_s);
  poses_.push_back(result.T_w_s);
  stamps_.push_back(stamp);
  result.map_points = edge_map_.NumPoints() + plane_map_.NumPoints();
  return result;
}

FrameResult LidarOdometry::ProcessScan(const LidarScan& scan, const StageObserver& observer) {
  return ProcessScan(LidarScan(scan), observer);
}

FrameResult LidarOdometry::ProcessScan(LidarScan&& scan, const StageObserver& observer) {
  Notify(observer, Stage::kRings);
  if (!impl_->generic) AssignScanRings(&scan);
  Notify(observer, Stage::kFeatures);
  const bool has_time = scan.time.size() == scan.size() && !scan.empty();
  // generic: no spinning order, so no time without the scan's own (deskew on is then a no-op).
  const bool deskew = (options_.deskew == DeskewMode::kOn && (has_time || !impl_->generic)) ||
                      (options_.deskew == DeskewMode::kAuto && has_time);
  ScanFeatures& features = impl_->features;  // kept across scans: no per-scan heap churn
  std::string error;
  // The first scan is not registered: all its features seed the map (a one-scan map of the
  // capped features is too sparse for the 1 m search of the next scan at speed).
  const bool seed_all = poses_.empty();
  int steps = 1;  // > 1 after a gap in the scan times: the start path (RegisterToMap)
  SE3d T_w_s_pred = options_.restart_from_stamps ? PredictPoseAt(poses_, stamps_, scan.timestamp,
                                                                 options_.constant_velocity, &steps)
                                                 : PredictPose(poses_, options_.constant_velocity);
  PredictAfterWideStart(scan.timestamp, &T_w_s_pred);
  if (steps > 1) impl_->registered_streak = 0;
  impl_->stamp = scan.timestamp;
  Extractors x;
  x.rings = &impl_->feature_extractor;
  if (impl_->generic && !(deskew && has_time)) x.geometric = &impl_->geometric_extractor;
  if (impl_->generic && deskew && has_time) {  // the sweep motion: constant velocity, or search
    x.sweep = &impl_->sweep_extractor;
    const std::size_t n = poses_.size();
    x.T_sweep = n >= 2 ? poses_[n - 2].Inverse() * poses_[n - 1]
                       : x.sweep->SearchForwardMotion(scan, options_.features, options_.generic);
    if (n == 1) T_w_s_pred = poses_.back() * x.T_sweep;
  }
  if (!ExtractScanFeatures(scan, options_, deskew, seed_all, x, &features, &error)) {
    Notify(observer, Stage::kDone);
    return SkipFrame(error, scan.timestamp);
  }
  // A generic first sweep seeds the map deskewed with its searched motion (sweep_motion.h).
  const bool seed_deskewed = x.sweep && poses_.empty();
  if (seed_deskewed) DeskewScanPoints(x.T_sweep, options_.features.scan_period, &features);
  FrameResult result;
  result.features = features.stats;
  RegisterToMap(T_w_s_pred, deskew && !seed_deskewed, observer, &features, &result);
  Notify(observer, Stage::kMapUpdate);
  UpdateMap(deskew && !seed_deskewed, &features, &result);
  Notify(observer, Stage::kDone);
  return result;
}

void LidarOdometry::AssignScanRings(LidarScan* scan) {
  const RingSource source = options_.ring_source;
  const bool has_ring = scan->ring.size() == scan->size();
  if (source == RingSource::kScanOrder || (source == RingSource::kAuto && !has_ring)) {
    sensor::AssignRingsFromScanOrder(scan);
  } else if (source == RingSource::kElevation ||
             (source == RingSource::kAutoElevation && !has_ring)) {
    if (!impl_->sensor) impl_->sensor = sensor::AutoDetectSensor(*scan);
    scan->ring.clear();
    sensor::AssignRings(scan, *impl_->sensor);
  }
}

void LidarOdometry::RegisterToMap(const SE3d& T_w_s_pred, bool deskew,
                                  const StageObserver& observer, ScanFeatures* features,
                                  FrameResult* result) {
  const LidarOdometryOptions& o = options_;
  // While the map holds the raw seed scan, this scan registers raw against it (see UpdateMap).
  result->deskewed = deskew && !poses_.empty() && !impl_->seed;
  if (result->deskewed) {
    impl_->raw_edges = features->edges;
    impl_->raw_planes = features->planes;
    DeskewFeatures(T_w_s_pred, features);
  }
  result->edge_points = static_cast<int>(features->edges.size());
  result->plane_points = static_cast<int>(features->planes.size());
  result->T_w_s = T_w_s_pred;
  result->ok = true;  // the first scan (or a map still too small) is kept at the prediction
  if (poses_.empty() || edge_map_.NumPoints() + plane_map_.NumPoints() <
                            static_cast<std::size_t>(o.min_correspondences))
    return;
  const bool start = impl_->registered_streak < 2 && o.start_distance > 0.0;
  // No velocity yet (only the first scan registered) and a gap since it: the wide start.
  const double periods = start && impl_->registered_total == 1 ? PeriodsSinceSeed() : 0.0;
  const SE3d T_w_s_anchor = !start          ? T_w_s_pred
                            : periods > 1.5 ? RegisterWideStart(periods, observer, features, result)
                                            : RegisterStart(observer, features, result);
  const bool ok =
      RunRounds(o, edge_map_, plane_map_, T_w_s_anchor, start, observer, features, result);
  if (!ok) result->T_w_s = T_w_s_anchor;
  // A poor fit from the prediction (a restart the gap check missed): again through the start.
  const bool poor =
      !ok || result->plane_correspondences <
                 o.restart_min_plane_match * static_cast<double>(result->plane_points);
  if (start || !poor || o.start_distance <= 0.0 || o.restart_min_plane_match <= 0.0) return;
  const FeatureStats stats = result->features;
  *result = FrameResult();
  result->T_w_s = T_w_s_pred;
  result->features = stats;
  result->deskewed = deskew && !impl_->seed;
  result->edge_points = static_cast<int>(features->edges.size());
  result->plane_points = static_cast<int>(features->planes.size());
  result->restarted = true;
  const SE3d T_w_s_start = RegisterStart(observer, features, result);
  if (!RunRounds(o, edge_map_, plane_map_, T_w_s_start, true, observer, features, result))
    result->T_w_s = T_w_s_start;
}

// Scan periods from the first registered scan to the one being processed: from the scan times
// when both are known, else the frame slots between them (skipped frames).
double LidarOdometry::PeriodsSinceSeed() const {
  const double elapsed = impl_->stamp - stamps_[impl_->seed_slot];
  const double period = options_.features.scan_period;
  if (elapsed > 0.0 && period > 0.0) return elapsed / period;
  return static_cast<double>(poses_.size() - impl_->seed_slot);
}

LidarOdometryOptions StartStageOptions(const LidarOdometryOptions& o, double d) {
  const double k = d / std::min(o.max_correspondence_distance, o.plane_map.voxel_size);
  LidarOdometryOptions s = o;
  s.max_correspondence_distance = d;
  for (VoxelMapOptions* m : {&s.edge_map, &s.plane_map}) {
    m->min_point_distance *= d / m->voxel_size;
    m->voxel_size = d;
  }
  s.plane_sigma *= k;
  s.edge_sigma *= k;
  s.plane_max_residual *= k;
  s.convergence_translation *= k;
  s.convergence_rotation_deg *= k;
  return s;
}

// The coarse-to-fine start (LidarOdometryOptions::start_distance) from the prediction: each stage
// registers against the local map re-sampled at its distance. Returns the pose reached, which the
// normal registration starts from and keeps along degenerate directions.
SE3d LidarOdometry::RegisterStart(const StageObserver& observer, ScanFeatures* features,
                                  FrameResult* result) {
  const LidarOdometryOptions& o = options_;
  const std::vector<Eigen::Vector3d> edges_w = edge_map_.Points(), planes_w = plane_map_.Points();
  bool deskew_first_round = false;
  for (double d = o.start_distance; d > o.max_correspondence_distance * (1.0 + 1e-9); d *= 0.5) {
    const LidarOdometryOptions s = StartStageOptions(o, d);
    VoxelMap edge_map(s.edge_map), plane_map(s.plane_map);
    edge_map.AddPoints(edges_w);
    plane_map.AddPoints(planes_w);
    const SE3d T_w_s_before = result->T_w_s;
    result->association_rounds = 0;
    if (!RunRounds(s, edge_map, plane_map, result->T_w_s, deskew_first_round, observer, features,
                   result))
      result->T_w_s = T_w_s_before;  // a stage that fails leaves the pose to the next one
    result->start_rounds += result->association_rounds;
    deskew_first_round = true;
  }
  result->ok = true;
  result->error.clear();
  result->association_rounds = 0;
  result->solver_iterations = 0;
  return result->T_w_s;
}

// The association rounds (association_rounds, up to max_association_rounds while the pose moves)
// of options o from result->T_w_s against the maps; degenerate directions are kept at
// T_w_s_anchor. False when a round finds too few correspondences or the solver fails.
bool LidarOdometry::RunRounds(const LidarOdometryOptions& o, const VoxelMap& edge_map,
                              const VoxelMap& plane_map, const SE3d& T_w_s_anchor,
                              bool deskew_first_round, const StageObserver& observer,
                              ScanFeatures* features, FrameResult* result) {
  const int max_rounds = std::max(o.association_rounds, o.max_association_rounds);
  for (int round = 0; round < max_rounds; ++round) {
    Notify(observer, Stage::kCorrespondences);
    if ((round > 0 || deskew_first_round) && result->deskewed)
      DeskewFeatures(result->T_w_s, features);
    const int found =
        impl_->FindCorrespondences(edge_map, plane_map, *features, result->T_w_s, round == 0, o);
    result->plane_correspondences = static_cast<int>(impl_->planes.size());
    result->edge_correspondences = static_cast<int>(impl_->edges.size());
    result->ok = found >= o.min_correspondences;
    if (!result->ok) {
      result->error = "too few correspondences (" + std::to_string(found) + ")";
      return false;
    }
    Notify(observer, Stage::kSolve);
    const SE3d T_w_s_before = result->T_w_s;
    result->ok = SolveRound(o, T_w_s_anchor, result);
    if (!result->ok) return false;
    result->association_rounds = round + 1;
    const Vector6d step = result->T_w_s.Minus(T_w_s_before);
    const bool converged = step.tail<3>().norm() < o.convergence_translation &&
                           step.head<3>().norm() < o.convergence_rotation_deg * M_PI / 180.0;
    if (round + 1 >= o.association_rounds && converged) break;
  }
  return true;
}

void LidarOdometry::DeskewFeatures(const SE3d& T_w_s, ScanFeatures* features) const {
  const SE3d T_s_prev_s = poses_.back().Inverse() * T_w_s;  // the motion over this sweep
  features->edges = impl_->raw_edges;
  features->planes = impl_->raw_planes;
  DeskewScanPoints(T_s_prev_s, options_.features.scan_period, features);
}

// One solve from result->T_w_s, remapped to the anchor along degenerate directions.
bool LidarOdometry::SolveRound(const LidarOdometryOptions& o, const SE3d& T_w_s_anchor,
                               FrameResult* result) {
  LidarResiduals& residuals = impl_->residuals;  // values: no heap per correspondence
  residuals.planes.clear(), residuals.edges.clear();
  for (const Match& m : impl_->planes)
    residuals.planes.push_back(PlaneResidual::Create(m.p_s, m.d_w, m.x_w, o.plane_sigma));
  for (const Match& m : impl_->edges)
    residuals.edges.push_back(EdgeResidual::CreateFromDirection(m.p_s, m.x_w, m.d_w, o.edge_sigma));
  const PoseSolverOptions solver_options{o.max_iterations};
  SE3d T_w_s = result->T_w_s;
  const PoseSolverSummary summary = SolvePose(residuals, impl_->loss.get(), solver_options, &T_w_s);
  result->solver_iterations += summary.iterations;
  result->final_cost = summary.final_cost;
  if (!summary.usable || !T_w_s.translation().allFinite() ||
      !T_w_s.rotation().coeffs().allFinite()) {
    result->error = "solver failed: " + summary.message;
    return false;
  }
  // Degeneracy from the normal equations at the solution (rows: a plane 1, an edge 2).
  const int rows = static_cast<int>(impl_->planes.size() + 2 * impl_->edges.size());
  result->degeneracy = AnalyseDegeneracy(summary.normal_equations.H, rows, CriterionFor(o));
  result->T_w_s =
      o.handle_degeneracy ? RemapSolution(T_w_s_anchor, T_w_s, result->degeneracy) : T_w_s;
  return true;
}

void LidarOdometry::UpdateMap(bool deskew, ScanFeatures* features, FrameResult* result) {
  const LidarOdometryOptions& o = options_;
  if (result->ok && result->deskewed) DeskewFeatures(result->T_w_s, features);
  const bool add = result->ok || edge_map_.NumPoints() + plane_map_.NumPoints() <
                                     static_cast<std::size_t>(o.min_correspondences);
  if (add && result->association_rounds > 0 && impl_->seed) {
    RebuildMapFromSeed(result->T_w_s, features);
    result->deskewed = result->map_rebuilt = true;
  } else if (add && deskew && poses_.empty()) {
    impl_->seed = *features;
    impl_->T_w_s_seed = result->T_w_s;
  }
  if (!add) {
    features->edges.clear();
    features->planes.clear();
  }
  const bool remove_far = ++impl_->frames_since_cleanup >= std::max(1, o.map_cleanup_every);
  if (remove_far) impl_->frames_since_cleanup = 0;
  UpdateLocalMap(result->T_w_s, remove_far, &features->edges, &features->planes, &edge_map_,
                 &plane_map_);
  const bool registered = result->ok && (result->association_rounds > 0 || poses_.empty());
  impl_->registered_streak = registered ? impl_->registered_streak + 1 : 0;
  if (registered && impl_->registered_total++ == 0) impl_->seed_slot = poses_.size();
  poses_.push_back(result->T_w_s);
  stamps_.push_back(impl_->stamp);
  result->map_points = edge_map_.NumPoints() + plane_map_.NumPoints();
}

// The seed scan, raw in the map, and this scan, registered raw against it (both distorted alike):
// both are deskewed with the motion between them and the map rebuilt from them (else the raw
// first scan stays in the map). Measured on 40 distorted sweeps (RPE over 39 pairs):
//   plucker sim lidar --out sim_dist --scene urban --frames 40 --sensor vlp32 --distortion
//   plucker lidar --data sim_dist --out dist.txt && plucker eval rpe --gt sim_dist/poses.txt
//   --est dist.txt
// with this step: translation mean 7.3 mm, max 27 mm, rotation max 0.29 deg; without it: mean
// 23.8 mm, max 0.375 m and 1.41 deg (the first pair); deskew off: mean 13.5 mm.
void LidarOdometry::RebuildMapFromSeed(const SE3d& T_w_s, ScanFeatures* features) {
  ScanFeatures& seed = *impl_->seed;
  const SE3d T_s_seed_s = impl_->T_w_s_seed.Inverse() * T_w_s;
  DeskewScanPoints(T_s_seed_s, options_.features.scan_period, &seed);
  DeskewScanPoints(T_s_seed_s, options_.features.scan_period, features);
  edge_map_.Clear();
  plane_map_.Clear();
  UpdateLocalMap(impl_->T_w_s_seed, false, &seed.edges, &seed.planes, &edge_map_, &plane_map_);
  impl_->seed.reset();
}

}  // namespace lidar
}  // namespace plucker
