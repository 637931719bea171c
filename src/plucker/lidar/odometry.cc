#include "plucker/lidar/odometry.h"

#include <ceres/loss_function.h>

#include <Eigen/Eigenvalues>
#include <chrono>
#include <ctime>
#include <optional>
#include <stdexcept>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "plucker/factors/lidar_factors.h"
#include "plucker/lidar/deskew.h"
#include "plucker/lidar/pose_solver.h"
#include "plucker/lidar/sensor_model.h"

namespace plucker {
namespace lidar {
namespace {

using Clock = std::chrono::steady_clock;
double MsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

struct PlaneMatch {
  Eigen::Vector3d p_s, m_w, q_w;
};
struct EdgeMatch {
  Eigen::Vector3d p_s, a_w, u_w;
};

// Mean and covariance of a few points, eigen-decomposed (ascending eigenvalues).
struct LocalFit {
  Eigen::Vector3d mean;
  Eigen::Vector3d eigenvalues;
  Eigen::Matrix3d eigenvectors;
};
LocalFit Fit(const std::vector<Eigen::Vector3d>& pts) {
  LocalFit fit;
  fit.mean.setZero();
  for (const auto& p : pts) fit.mean += p;
  fit.mean /= static_cast<double>(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) {
    const Eigen::Vector3d d = p - fit.mean;
    cov.noalias() += d * d.transpose();
  }
  cov /= static_cast<double>(pts.size());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(cov);
  fit.eigenvalues = solver.eigenvalues();
  fit.eigenvectors = solver.eigenvectors();
  return fit;
}

// Every `stride`-th element so that at most `cap` remain (times alongside when present).
void StrideSample(int cap, std::vector<Eigen::Vector3d>* v, std::vector<double>* times) {
  if (cap <= 0 || static_cast<int>(v->size()) <= cap) return;
  const bool with_times = times->size() == v->size();
  const double step = static_cast<double>(v->size()) / cap;
  std::vector<Eigen::Vector3d> out;
  std::vector<double> out_times;
  out.reserve(cap);
  for (int i = 0; i < cap; ++i) {
    const std::size_t j = static_cast<std::size_t>(i * step);
    out.push_back((*v)[j]);
    if (with_times) out_times.push_back((*times)[j]);
  }
  v->swap(out);
  if (with_times) times->swap(out_times);
}

}  // namespace

double ThreadCpuMs() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

RobustLoss ParseRobustLoss(const std::string& name) {
  if (name == "huber") return RobustLoss::kHuber;
  if (name == "cauchy") return RobustLoss::kCauchy;
  if (name == "none") return RobustLoss::kNone;
  throw std::invalid_argument("unknown loss '" + name + "' (huber, cauchy, none)");
}
DeskewMode ParseDeskewMode(const std::string& name) {
  if (name == "auto") return DeskewMode::kAuto;
  if (name == "on") return DeskewMode::kOn;
  if (name == "off") return DeskewMode::kOff;
  throw std::invalid_argument("unknown deskew mode '" + name + "' (auto, on, off)");
}
RingSource ParseRingSource(const std::string& name) {
  if (name == "auto") return RingSource::kAuto;
  if (name == "scan_order") return RingSource::kScanOrder;
  if (name == "elevation") return RingSource::kElevation;
  if (name == "auto_elevation") return RingSource::kAutoElevation;
  throw std::invalid_argument("unknown ring source '" + name +
                              "' (auto, scan_order, elevation, auto_elevation)");
}

class LidarOdometry::Impl {
 public:
  explicit Impl(int num_threads) : num_threads(std::max(1, num_threads)) {
    if (this->num_threads > 1) arena = std::make_unique<tbb::task_arena>(this->num_threads);
  }

  // Stage clock: CPU time of this thread when single-threaded (robust to a loaded machine),
  // wall-clock otherwise (the work is spread over threads).
  double Now() const {
    if (num_threads == 1) return ThreadCpuMs();
    return std::chrono::duration<double, std::milli>(Clock::now().time_since_epoch()).count();
  }

  // matches = the successful match(point) over `points`, in point order; in parallel chunks when
  // num_threads > 1 (the same result either way).
  template <typename Match, typename MatchFn>
  void FindMatches(const std::vector<Eigen::Vector3d>& points, const MatchFn& match_fn,
                   std::vector<Match>* matches) {
    matches->clear();
    if (!arena) {
      Match m;
      for (const Eigen::Vector3d& p : points)
        if (match_fn(p, &neighbours, &m)) matches->push_back(m);
      return;
    }
    constexpr std::size_t kChunk = 256;
    const std::size_t chunks = (points.size() + kChunk - 1) / kChunk;
    std::vector<std::vector<Match>> parts(chunks);
    arena->execute([&] {
      tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
        std::vector<Eigen::Vector3d> nb;
        Match m;
        for (std::size_t i = c * kChunk; i < std::min(points.size(), (c + 1) * kChunk); ++i)
          if (match_fn(points[i], &nb, &m)) parts[c].push_back(m);
      });
    });
    for (const auto& part : parts) matches->insert(matches->end(), part.begin(), part.end());
  }

  int num_threads;
  std::unique_ptr<tbb::task_arena> arena;
  std::unique_ptr<ceres::LossFunction> loss;
  std::optional<SensorModel> sensor;
  std::vector<Eigen::Vector3d> neighbours;
  std::vector<PlaneMatch> planes;
  std::vector<EdgeMatch> edges;
  std::vector<std::unique_ptr<ceres::CostFunction>> residuals;
  int frames_since_cleanup = 0;
  // Per-scan buffers kept across scans (no multi-MB allocation per scan on long sequences).
  FeatureExtractor feature_extractor;
  ScanFeatures features;
  std::vector<Eigen::Vector3d> raw_edges, raw_planes;

  // The scan that seeded the map when it could not be deskewed (no motion known yet), kept raw
  // until the next scan is registered: then it is deskewed with that motion and the map rebuilt.
  struct Seed {
    SE3d T_w_s;
    std::vector<Eigen::Vector3d> edges, planes;
    std::vector<double> edge_times, plane_times;
  };
  std::optional<Seed> seed;
};

LidarOdometry::LidarOdometry(const LidarOdometryOptions& options)
    : options_(options),
      edge_map_(options.edge_map),
      plane_map_(options.plane_map),
      impl_(std::make_unique<Impl>(options.num_threads)) {
  switch (options_.loss) {
    case RobustLoss::kHuber:
      impl_->loss = std::make_unique<ceres::HuberLoss>(options_.loss_scale);
      break;
    case RobustLoss::kCauchy:
      impl_->loss = std::make_unique<ceres::CauchyLoss>(options_.loss_scale);
      break;
    case RobustLoss::kNone:
      break;
  }
  if (options_.sensor != "auto") impl_->sensor = FromName(options_.sensor);
}

LidarOdometry::~LidarOdometry() = default;

SE3d LidarOdometry::Predict() const {
  if (poses_.empty()) return SE3d();
  if (poses_.size() < 2 || !options_.constant_velocity) return poses_.back();
  const SE3d& last = poses_.back();
  return last * (poses_[poses_.size() - 2].Inverse() * last);
}

FrameResult LidarOdometry::SkipFrame(const std::string& reason) {
  FrameResult result;
  result.ok = false;
  result.error = reason;
  result.T_w_s = Predict();
  poses_.push_back(result.T_w_s);
  result.map_points = edge_map_.NumPoints() + plane_map_.NumPoints();
  return result;
}

FrameResult LidarOdometry::ProcessScan(const LidarScan& scan) {
  return ProcessScan(LidarScan(scan));
}

FrameResult LidarOdometry::ProcessScan(LidarScan&& scan) {
  const auto t_start = Clock::now();
  const double cpu_start = ThreadCpuMs();
  FrameResult result;
  const LidarOdometryOptions& o = options_;

  // 1. Rings.
  double t0 = impl_->Now();
  const bool has_ring = scan.ring.size() == scan.size();
  if (o.ring_source == RingSource::kScanOrder ||
      (o.ring_source == RingSource::kAuto && !has_ring)) {
    AssignRingsFromScanOrder(&scan);
  } else if (o.ring_source == RingSource::kElevation ||
             (o.ring_source == RingSource::kAutoElevation && !has_ring)) {
    if (!impl_->sensor) impl_->sensor = AutoDetectSensor(scan);
    scan.ring.clear();
    AssignRings(&scan, *impl_->sensor);
  }
  result.timing.rings = (impl_->Now() - t0);

  // 2. Features (+ deskew).
  t0 = impl_->Now();
  const bool deskew =
      o.deskew == DeskewMode::kOn ||
      (o.deskew == DeskewMode::kAuto && scan.time.size() == scan.size() && !scan.empty());
  FeatureOptions feature_options = o.features;
  feature_options.compute_times = deskew;
  feature_options.num_threads = o.num_threads;
  ScanFeatures& features = impl_->features;
  std::string error;
  if (!impl_->feature_extractor.Extract(scan, feature_options, &features, &error)) {
    FrameResult skipped = SkipFrame(error);
    skipped.timing.total = MsSince(t_start);
    skipped.timing.cpu = ThreadCpuMs() - cpu_start;
    return skipped;
  }
  result.features = features.stats;
  const SE3d T_pred = Predict();
  if (!o.use_edges) features.edges.clear();
  StrideSample(o.max_edge_points, &features.edges, &features.edge_times);
  StrideSample(o.max_plane_points, &features.planes, &features.plane_times);
  // Deskew: the feature points are moved to the scan-start frame with the motion over this
  // sweep, T_{k-1}^-1 T (constant velocity), re-done with the current estimate in every round.
  // While the map holds the raw seed scan (below), scans register raw against it: both are
  // distorted alike by the sweep, which biases the estimate less than a deskewed scan against a
  // raw map.
  const bool seed_pending = impl_->seed.has_value();
  const bool can_deskew = deskew && !poses_.empty() && !seed_pending;
  std::vector<Eigen::Vector3d>& raw_edges = impl_->raw_edges;
  std::vector<Eigen::Vector3d>& raw_planes = impl_->raw_planes;
  if (can_deskew) {
    raw_edges = features.edges;
    raw_planes = features.planes;
  }
  std::vector<Eigen::Vector3d>& edge_pts = features.edges;
  std::vector<Eigen::Vector3d>& plane_pts = features.planes;
  auto deskew_with = [&](const SE3d& T_w_s) {
    if (!can_deskew) return;
    const SE3d motion = poses_.back().Inverse() * T_w_s;
    edge_pts = raw_edges;
    plane_pts = raw_planes;
    DeskewPoints(motion, o.features.scan_period, features.edge_times, &edge_pts);
    DeskewPoints(motion, o.features.scan_period, features.plane_times, &plane_pts);
    result.deskewed = true;
  };
  deskew_with(T_pred);
  result.edge_points = static_cast<int>(edge_pts.size());
  result.plane_points = static_cast<int>(plane_pts.size());
  result.timing.features = (impl_->Now() - t0);

  SE3d T = T_pred;
  const bool first = poses_.empty() || plane_map_.NumPoints() + edge_map_.NumPoints() <
                                           static_cast<std::size_t>(o.min_correspondences);
  bool registered = first;
  if (!first) {
    const int k = std::min(o.num_neighbours, 16);
    const double max_d = std::min(o.max_correspondence_distance, plane_map_.options().voxel_size);
    const int max_rounds = std::max(o.association_rounds, o.max_association_rounds);
    for (int round = 0; round < max_rounds; ++round) {
      // 3. Correspondences (after deskewing with the current estimate).
      t0 = impl_->Now();
      if (round > 0) deskew_with(T);
      const Eigen::Matrix3d R = T.RotationMatrix();
      const Eigen::Vector3d t = T.translation();
      const double edge_max_d = std::min(max_d, edge_map_.options().voxel_size);
      auto match_plane = [&](const Eigen::Vector3d& p_s, std::vector<Eigen::Vector3d>* nb,
                             PlaneMatch* match) {
        if (plane_map_.KNearest(R * p_s + t, k, max_d, nb) < k) return false;
        const LocalFit fit = Fit(*nb);
        const Eigen::Vector3d m = fit.eigenvectors.col(0);
        for (const auto& q : *nb)
          if (std::abs(m.dot(q - fit.mean)) > o.plane_max_residual) return false;
        *match = {p_s, m, fit.mean};
        return true;
      };
      auto match_edge = [&](const Eigen::Vector3d& p_s, std::vector<Eigen::Vector3d>* nb,
                            EdgeMatch* match) {
        if (edge_map_.KNearest(R * p_s + t, k, edge_max_d, nb) < k) return false;
        const LocalFit fit = Fit(*nb);
        if (fit.eigenvalues(2) <= o.edge_eigen_ratio * fit.eigenvalues(1)) return false;
        *match = {p_s, fit.mean, fit.eigenvectors.col(2)};
        return true;
      };
      impl_->FindMatches(plane_pts, match_plane, &impl_->planes);
      impl_->FindMatches(edge_pts, match_edge, &impl_->edges);
      result.plane_correspondences = static_cast<int>(impl_->planes.size());
      result.edge_correspondences = static_cast<int>(impl_->edges.size());
      result.timing.correspondences += (impl_->Now() - t0);
      if (result.plane_correspondences + result.edge_correspondences < o.min_correspondences) {
        registered = false;
        error = "too few correspondences (" +
                std::to_string(result.plane_correspondences + result.edge_correspondences) + ")";
        break;
      }

      // 4. Solve.
      t0 = impl_->Now();
      impl_->residuals.clear();
      for (const PlaneMatch& m : impl_->planes)
        impl_->residuals.emplace_back(
            PointToPlaneFactor::Create(m.p_s, m.m_w, m.q_w, o.plane_sigma));
      for (const EdgeMatch& m : impl_->edges)
        impl_->residuals.emplace_back(PointToEdgeFactor::Create(m.p_s, m.a_w + 0.1 * m.u_w,
                                                                m.a_w - 0.1 * m.u_w, o.edge_sigma));
      PoseSolverOptions solver_options;
      solver_options.max_iterations = o.max_iterations;
      SE3d T_solved = T;
      const PoseSolverSummary summary =
          SolvePose(impl_->residuals, impl_->loss.get(), solver_options, &T_solved);
      result.solver_iterations += summary.iterations;
      result.final_cost = summary.final_cost;
      if (!summary.usable || !T_solved.translation().allFinite() ||
          !T_solved.rotation().coeffs().allFinite()) {
        registered = false;
        error = "solver failed: " + summary.message;
        result.timing.solve += (impl_->Now() - t0);
        break;
      }

      // Degeneracy at the solution; keep the prediction along poorly constrained directions.
      NormalEquations normal;
      for (const PlaneMatch& m : impl_->planes)
        normal.AddPlane(T_solved, m.p_s, m.m_w, o.plane_sigma);
      for (const EdgeMatch& m : impl_->edges) normal.AddEdge(T_solved, m.p_s, m.u_w, o.edge_sigma);
      DegeneracyCriterion criterion;
      criterion.translation_ratio = o.degeneracy_threshold;
      criterion.rotation_ratio = o.degeneracy_rotation_threshold;
      criterion.max_translation_information =
          o.degeneracy_max_normal_alignment / (o.plane_sigma * o.plane_sigma);
      criterion.max_rotation_information = o.degeneracy_max_rotation_information;
      result.degeneracy = normal.Analyse(criterion);
      if (o.handle_degeneracy) T_solved = RemapSolution(T_pred, T_solved, result.degeneracy);
      const Vector6d step = T_solved.Minus(T);
      T = T_solved;
      registered = true;
      result.timing.solve += (impl_->Now() - t0);
      result.association_rounds = round + 1;
      const bool converged = step.tail<3>().norm() < o.convergence_translation &&
                             step.head<3>().norm() < o.convergence_rotation_deg * M_PI / 180.0;
      if (round + 1 >= o.association_rounds && converged) break;
    }
  }

  // 5. Map update.
  t0 = impl_->Now();
  if (registered && !first) deskew_with(T);
  result.ok = registered;
  result.error = registered ? std::string() : error;
  result.T_w_s = registered ? T : T_pred;
  if (registered || edge_map_.NumPoints() + plane_map_.NumPoints() <
                        static_cast<std::size_t>(o.min_correspondences)) {
    if (deskew && !can_deskew && !seed_pending)
      impl_->seed =
          Impl::Seed{result.T_w_s, edge_pts, plane_pts, features.edge_times, features.plane_times};
    if (registered && !first && seed_pending) {
      // The sweep motion of the seed scan and of this one, by constant velocity: the motion
      // between them. Both are deskewed with it and the map is rebuilt from them.
      Impl::Seed& seed = *impl_->seed;
      const SE3d motion = seed.T_w_s.Inverse() * result.T_w_s;
      DeskewPoints(motion, o.features.scan_period, seed.edge_times, &seed.edges);
      DeskewPoints(motion, o.features.scan_period, seed.plane_times, &seed.planes);
      DeskewPoints(motion, o.features.scan_period, features.edge_times, &edge_pts);
      DeskewPoints(motion, o.features.scan_period, features.plane_times, &plane_pts);
      result.deskewed = true;
      for (auto& p : seed.edges) p = seed.T_w_s * p;
      for (auto& p : seed.planes) p = seed.T_w_s * p;
      edge_map_.Clear();
      plane_map_.Clear();
      edge_map_.AddPoints(seed.edges);
      plane_map_.AddPoints(seed.planes);
      impl_->seed.reset();
      result.map_rebuilt = true;
    }
    const Eigen::Matrix3d R = result.T_w_s.RotationMatrix();
    const Eigen::Vector3d t = result.T_w_s.translation();
    for (auto& p : edge_pts) p = R * p + t;
    for (auto& p : plane_pts) p = R * p + t;
    edge_map_.AddPoints(edge_pts);
    plane_map_.AddPoints(plane_pts);
  }
  if (++impl_->frames_since_cleanup >= std::max(1, o.map_cleanup_every)) {
    impl_->frames_since_cleanup = 0;
    edge_map_.RemoveFar(result.T_w_s.translation());
    plane_map_.RemoveFar(result.T_w_s.translation());
  }
  poses_.push_back(result.T_w_s);
  result.map_points = edge_map_.NumPoints() + plane_map_.NumPoints();
  result.timing.map_update = (impl_->Now() - t0);
  result.timing.total = MsSince(t_start);
  result.timing.cpu = ThreadCpuMs() - cpu_start;
  return result;
}

}  // namespace lidar
}  // namespace plucker
