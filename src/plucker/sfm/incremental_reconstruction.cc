#include "plucker/sfm/incremental_reconstruction.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <numeric>
#include <random>
#include <stdexcept>
#include <thread>

#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/flann.hpp>
#include <opencv2/imgproc.hpp>

#include "plucker/ba/bundle_adjustment.h"
#include "plucker/geometry/median.h"
#include "plucker/geometry/point_projection.h"
#include "plucker/geometry/so3.h"
#include "plucker/vision/pnp_ransac.h"

namespace plucker {
namespace sfm {

const char* ToString(SfmStage stage) {
  switch (stage) {
    case SfmStage::kMatching:
      return "matching";
    case SfmStage::kInitialization:
      return "initialization";
    case SfmStage::kRegistration:
      return "registration";
    case SfmStage::kTriangulation:
      return "triangulation";
    case SfmStage::kLines:
      return "lines";
    case SfmStage::kAdjustment:
      return "adjustment";
    case SfmStage::kDone:
      return "done";
  }
  return "?";
}

vision::LineMatcherOptions SfmOptions::DefaultLineMatcher() {
  vision::LineMatcherOptions o;
  o.max_midpoint_distance_px = 0.0;  // wide baselines: the epipolar gate locates instead
  o.max_angle_deg = 30.0;
  o.max_hamming = 60;
  o.min_epipolar_overlap = 0.5;
  return o;
}

// ---------------------------------------------------------------------------------------------
// Features.

ViewFeatures ExtractFeatures(const cv::Mat& gray, const FeatureOptions& options) {
  if (gray.empty() || gray.type() != CV_8UC1)
    throw std::invalid_argument("ExtractFeatures: needs a non-empty CV_8UC1 image");
  ViewFeatures f;
  f.width = gray.cols;
  f.height = gray.rows;
  cv::Mat small = gray;
  const int side = std::max(gray.cols, gray.rows);
  if (options.detection_max_side > 0 && side > options.detection_max_side) {
    const double s = static_cast<double>(options.detection_max_side) / side;
    cv::resize(gray, small,
               cv::Size(std::max(1, static_cast<int>(std::lround(gray.cols * s))),
                        std::max(1, static_cast<int>(std::lround(gray.rows * s)))),
               0, 0, cv::INTER_AREA);
  }
  const double sx = static_cast<double>(gray.cols) / small.cols;
  const double sy = static_cast<double>(gray.rows) / small.rows;
  std::vector<cv::KeyPoint> kps;
  cv::SIFT::create(options.max_keypoints)
      ->detectAndCompute(small, cv::noArray(), kps, f.descriptors);
  f.keypoints.reserve(kps.size());
  for (const cv::KeyPoint& k : kps)  // pixel centres: u = (u' + 0.5) s - 0.5
    f.keypoints.emplace_back((k.pt.x + 0.5) * sx - 0.5, (k.pt.y + 0.5) * sy - 0.5);
  if (f.descriptors.type() != CV_32F && !f.descriptors.empty())
    f.descriptors.convertTo(f.descriptors, CV_32F);

  if (options.detect_lines) {
    std::vector<vision::Segment2d> segs =
        vision::DetectLineSegments(gray, options.line_detector).segments;
    auto length = [](const vision::Segment2d& s) { return (s.head<2>() - s.tail<2>()).norm(); };
    segs.erase(std::remove_if(segs.begin(), segs.end(),
                              [&](const vision::Segment2d& s) {
                                return length(s) < options.min_line_length_px;
                              }),
               segs.end());
    std::stable_sort(segs.begin(), segs.end(),
                     [&](const auto& a, const auto& b) { return length(a) > length(b); });
    if (options.max_lines > 0 && static_cast<int>(segs.size()) > options.max_lines)
      segs.resize(options.max_lines);
    vision::LineDescriberOptions describe;
    describe.min_length_px = options.min_line_length_px * 0.5;
    f.lines = vision::DescribeLines(gray, segs, describe);
  }
  return f;
}

namespace {

using Obs = std::pair<int, int>;  // (view, feature index)

struct VerifiedPair {
  int a = -1, b = -1;
  std::vector<std::pair<int, int>> matches;  // keypoint indices (a, b), essential inliers
  SE3d T_b_a;                                // |t| = 1
  double median_angle_deg = 0.0;
};

struct PointTrack {
  std::vector<Obs> obs;
  std::vector<char> outlier;
  bool has_point = false;
  bool dead = false;  // rejected after triangulation: not tried again
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
};

struct LineTrack {
  std::vector<Obs> obs;
  std::vector<char> outlier;
  bool has_line = false;
  bool dead = false;
  int tried_views = 0;  // observation count at the last failed triangulation
  Line6d L_w = Line6d::Zero();
  Eigen::Vector3d start_w = Eigen::Vector3d::Zero(), end_w = Eigen::Vector3d::Zero();
};

// Union-find over integer nodes.
struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int Find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void Union(int a, int b) { parent[Find(a)] = Find(b); }
};

Eigen::Vector2d Normalized(const PinholeIntrinsics& K, const Eigen::Vector2d& uv) {
  return K.ToNormalized<double>(uv);
}

// A FLANN index (randomised kd-trees) over one view's descriptors. Built on one thread: the
// trees draw from the C library's rand(), so building them in a fixed order keeps the matches
// repeatable; the searches are deterministic and may run in parallel (one index per task).
std::unique_ptr<cv::flann::Index> BuildIndex(const cv::Mat& descriptors) {
  if (descriptors.rows < 2) return nullptr;
  return std::make_unique<cv::flann::Index>(descriptors, cv::flann::KDTreeIndexParams(4));
}

// Nearest neighbours of a in b (indexed by index_b) with the ratio test; each b in at most one
// match (the closest).
std::vector<std::pair<int, int>> MatchDescriptors(const cv::Mat& a, cv::flann::Index* index_b,
                                                  double ratio) {
  std::vector<std::pair<int, int>> out;
  if (a.rows < 2 || !index_b) return out;
  cv::Mat indices, squared;  // a.rows x 2; squared L2 distances
  index_b->knnSearch(a, indices, squared, 2, cv::flann::SearchParams(64));
  std::map<int, std::pair<float, int>> best_for_b;
  for (int i = 0; i < a.rows; ++i) {
    const int j = indices.at<int>(i, 0);
    const float d1 = std::sqrt(squared.at<float>(i, 0)), d2 = std::sqrt(squared.at<float>(i, 1));
    if (j < 0 || indices.at<int>(i, 1) < 0 || d1 >= ratio * d2) continue;
    auto it = best_for_b.find(j);
    if (it == best_for_b.end() || d1 < it->second.first) best_for_b[j] = {d1, i};
  }
  for (const auto& [bi, v] : best_for_b) out.emplace_back(v.second, bi);
  std::sort(out.begin(), out.end());
  return out;
}

// fn(0) ... fn(n - 1) on up to `threads` threads (the calling one included); fn must only
// write to its own outputs. The first exception thrown by fn is rethrown on the calling thread.
void ParallelFor(int n, int threads, const std::function<void(int)>& fn) {
  const int workers = std::min(std::max(1, threads), n);
  if (workers <= 1) {
    for (int i = 0; i < n; ++i) fn(i);
    return;
  }
  std::atomic<int> next{0};
  std::mutex error_mutex;
  std::exception_ptr error;
  const auto work = [&]() {
    for (int i = next++; i < n; i = next++) {
      try {
        fn(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < workers; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

class Reconstruction {
 public:
  Reconstruction(const PinholeIntrinsics& K, const std::vector<ViewFeatures>& views,
                 const SfmOptions& options, const SfmObserver& observer,
                 const SfmProgress& progress)
      : K_(K), views_(views), o_(options), observer_(observer), progress_(progress) {
    const int n = static_cast<int>(views.size());
    pose_.assign(n, std::nullopt);
    status_.assign(n, "not registered");
    failed_count_.assign(n, 0);
    kp_track_.resize(n);
    seg_track_.resize(n);
    for (int v = 0; v < n; ++v) {
      kp_track_[v].assign(views[v].keypoints.size(), -1);
      seg_track_[v].assign(views[v].lines.size(), -1);
      if (views[v].keypoints.empty()) status_[v] = "no features (unreadable or no texture)";
    }
  }

  SfmResult Run() {
    SfmResult r;
    r.stats.views = static_cast<int>(views_.size());
    Announce(SfmStage::kMatching);
    MatchAllPairs();
    BuildPointTracks();
    r.stats.verified_pairs = static_cast<int>(pairs_.size());
    r.stats.point_tracks = point_tracks_total_;
    Announce(SfmStage::kInitialization);
    std::string why;
    if (!Initialize(&why)) {
      Announce(SfmStage::kDone);
      r.message = why;
      return Finish(std::move(r));
    }
    Adjust(o_.local_iterations);
    while (RegisterNext()) {
    }
    Announce(SfmStage::kAdjustment);
    Adjust(o_.final_iterations);
    if (RejectOutliers() > 0) Adjust(o_.final_iterations);
    RejectOutliers();
    UpdateLineExtents();
    Announce(SfmStage::kDone);
    r.ok = true;
    return Finish(std::move(r));
  }

 private:
  void Announce(SfmStage s) {
    if (observer_) observer_(s);
  }
  void Progress(const std::string& m) {
    if (progress_) progress_(m);
  }
  int NumViews() const { return static_cast<int>(views_.size()); }

  // ----- matching -----
  // The pairs (a, b > a) of each view a are verified in parallel; pairs_ stays in (a, b) order.
  void MatchAllPairs() {
    const int n = NumViews();
    std::vector<std::unique_ptr<cv::flann::Index>> index(n);
    for (int b = 1; b < n; ++b) index[b] = BuildIndex(views_[b].descriptors);
    for (int a = 0; a < n; ++a) {
      std::vector<VerifiedPair> row(n);
      std::vector<char> ok(n, 0);
      ParallelFor(n - a - 1, o_.num_threads, [&](int k) {
        const int b = a + 1 + k;
        ok[b] = Verify(a, b, index[b].get(), &row[b]);
      });
      for (int b = a + 1; b < n; ++b)
        if (ok[b]) pairs_.push_back(std::move(row[b]));
      Progress("matched view " + std::to_string(a + 1) + "/" + std::to_string(n) + ", " +
               std::to_string(pairs_.size()) + " verified pairs");
    }
  }

  bool Verify(int a, int b, cv::flann::Index* index_b, VerifiedPair* p) const {
    const auto matches = MatchDescriptors(views_[a].descriptors, index_b, o_.match_ratio);
    if (static_cast<int>(matches.size()) < std::max(o_.min_pair_inliers, 5)) return false;
    std::vector<Eigen::Vector2d> xa, xb;
    for (const auto& [i, j] : matches) {
      xa.push_back(Normalized(K_, views_[a].keypoints[i]));
      xb.push_back(Normalized(K_, views_[b].keypoints[j]));
    }
    vision::EssentialPoseOptions eo;
    eo.threshold = o_.essential_threshold_px / (0.5 * (K_.fx + K_.fy));
    eo.confidence = 0.999;
    eo.take_first_of_several = true;
    const vision::EssentialPoseResult e = vision::EssentialPose(xa, xb, eo);
    if (!e.ok() || e.inliers < o_.min_pair_inliers) return false;
    const Eigen::Matrix3d& Re = e.R_b_a;
    p->a = a;
    p->b = b;
    p->T_b_a = SE3d(Re, e.t_b_a.normalized());
    std::vector<double> angles;
    for (std::size_t k = 0; k < matches.size(); ++k) {
      if (!e.inlier_mask[k]) continue;
      p->matches.push_back(matches[k]);
      const Eigen::Vector3d ra = xa[k].homogeneous().normalized();
      const Eigen::Vector3d rb = Re.transpose() * xb[k].homogeneous().normalized();
      angles.push_back(std::acos(std::clamp(ra.dot(rb), -1.0, 1.0)) * 180.0 / M_PI);
    }
    p->median_angle_deg = UpperMedian(angles);
    return true;
  }

  void BuildPointTracks() {
    const int n = NumViews();
    std::vector<int> offset(n + 1, 0);
    for (int v = 0; v < n; ++v) offset[v + 1] = offset[v] + static_cast<int>(kp_track_[v].size());
    UnionFind uf(offset[n]);
    std::vector<char> used(offset[n], 0);
    for (const VerifiedPair& p : pairs_)
      for (const auto& [i, j] : p.matches) {
        uf.Union(offset[p.a] + i, offset[p.b] + j);
        used[offset[p.a] + i] = used[offset[p.b] + j] = 1;
      }
    std::map<int, std::vector<Obs>> components;
    for (int v = 0; v < n; ++v)
      for (int k = 0; k < static_cast<int>(kp_track_[v].size()); ++k)
        if (used[offset[v] + k]) components[uf.Find(offset[v] + k)].emplace_back(v, k);
    std::vector<std::vector<Obs>> tracks;
    for (auto& [root, obs] : components) {
      std::vector<char> seen(n, 0);
      bool consistent = obs.size() >= 2;
      for (const Obs& o : obs) {
        if (seen[o.first]) consistent = false;
        seen[o.first] = 1;
      }
      if (consistent) tracks.push_back(std::move(obs));
    }
    point_tracks_total_ = static_cast<int>(tracks.size());
    if (o_.point_subset_seed > 0) {
      std::mt19937 rng(static_cast<std::mt19937::result_type>(o_.point_subset_seed));
      std::shuffle(tracks.begin(), tracks.end(), rng);
    } else {
      std::stable_sort(tracks.begin(), tracks.end(),
                       [](const auto& a, const auto& b) { return a.size() > b.size(); });
    }
    if (o_.max_points > 0 && static_cast<int>(tracks.size()) > o_.max_points)
      tracks.resize(o_.max_points);
    for (auto& obs : tracks) {
      PointTrack t;
      t.obs = std::move(obs);
      t.outlier.assign(t.obs.size(), 0);
      for (const Obs& o : t.obs) kp_track_[o.first][o.second] = static_cast<int>(tracks_.size());
      tracks_.push_back(std::move(t));
    }
  }

  // ----- initialisation -----
  bool Initialize(std::string* why) {
    const VerifiedPair* best = nullptr;
    for (const VerifiedPair& p : pairs_) {
      if (p.median_angle_deg < o_.min_init_angle_deg) continue;
      if (!best || p.matches.size() > best->matches.size()) best = &p;
    }
    if (!best) {
      *why = pairs_.empty() ? "no pair of views has enough verified matches (" +
                                  std::to_string(o_.min_pair_inliers) + " essential inliers)"
                            : "no verified pair has a median triangulation angle of " +
                                  std::to_string(o_.min_init_angle_deg) + " deg";
      return false;
    }
    pose_[best->a] = SE3d();
    pose_[best->b] = best->T_b_a.Inverse();
    order_ = {best->a, best->b};
    init_a_ = best->a;
    init_b_ = best->b;
    status_[best->a] = status_[best->b] = "registered";
    Announce(SfmStage::kTriangulation);
    const int points = TriangulatePoints();
    Progress("initial pair " + std::to_string(best->a) + "-" + std::to_string(best->b) + ": " +
             std::to_string(best->matches.size()) + " inliers, median angle " +
             std::to_string(best->median_angle_deg) + " deg, " + std::to_string(points) +
             " points");
    if (points < o_.min_pnp_inliers) {
      *why = "the initial pair triangulates only " + std::to_string(points) + " points";
      return false;
    }
    if (o_.use_lines) {
      Announce(SfmStage::kLines);
      MatchLines(best->b);
      TriangulateLines();
    }
    return true;
  }

  // ----- registration -----
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector2d>> Correspondences(int v,
                                                                           std::vector<int>* ids) {
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector2d>> c;
    for (int k = 0; k < static_cast<int>(kp_track_[v].size()); ++k) {
      const int t = kp_track_[v][k];
      if (t < 0 || !tracks_[t].has_point) continue;
      c.emplace_back(tracks_[t].p_w, views_[v].keypoints[k]);
      if (ids) ids->push_back(t);
    }
    return c;
  }

  bool RegisterNext() {
    Announce(SfmStage::kRegistration);
    int best = -1, best_count = 0;
    for (int v = 0; v < NumViews(); ++v) {
      if (pose_[v] || views_[v].keypoints.empty()) continue;
      const int count = static_cast<int>(Correspondences(v, nullptr).size());
      if (count <= failed_count_[v] * 1.2 + 1) continue;  // retry only with more support
      if (count > best_count) best = v, best_count = count;
    }
    if (best < 0 || best_count < o_.min_pnp_inliers) return false;
    const int v = best;
    std::vector<int> ids;
    const auto corr = Correspondences(v, &ids);
    std::vector<Eigen::Vector3d> obj;
    std::vector<Eigen::Vector2d> img;
    for (const auto& [p, uv] : corr) {
      obj.push_back(p);
      img.push_back(uv);
    }
    vision::PnpRansacOptions pnp;
    pnp.solver = vision::PnpSolver::kAp3p;
    pnp.iterations = 1000;
    pnp.threshold_px = o_.pnp_threshold_px;
    pnp.confidence = 0.9999;
    pnp.min_correspondences = 0;  // the caller checked best_count >= min_pnp_inliers
    pnp.min_inliers = o_.min_pnp_inliers;
    const vision::PnpRansacResult r = vision::PnpRansac(obj, img, K_, pnp);
    if (r.status == vision::PnpStatus::kNotFinite) {
      failed_count_[v] = best_count;
      status_[v] = "PnP gave a non-finite pose";
      return true;
    }
    if (!r.ok()) {
      failed_count_[v] = best_count;
      status_[v] = "PnP failed: " + std::to_string(r.inliers.size()) + " inliers of " +
                   std::to_string(best_count) + " correspondences";
      Progress("view " + std::to_string(v) + ": " + status_[v]);
      return true;  // other views may still register
    }
    const std::vector<int>& inliers = r.inliers;
    pose_[v] = r.T_c_w.Inverse();
    // Correspondences that PnP rejected are outliers of their tracks in this view.
    std::vector<char> is_inlier(corr.size(), 0);
    for (int i : inliers) is_inlier[i] = 1;
    for (std::size_t i = 0; i < corr.size(); ++i)
      if (!is_inlier[i]) MarkOutlier(&tracks_[ids[i]], v);
    order_.push_back(v);
    status_[v] = "registered";
    const int num_inliers = static_cast<int>(inliers.size());
    if (o_.use_lines) {
      Announce(SfmStage::kLines);
      MatchLines(v);
      CheckNewLineObservations(v);
    }
    RefinePose(v, o_.use_lines && num_inliers < o_.scarce_points);
    Announce(SfmStage::kTriangulation);
    const int new_points = TriangulatePoints();
    int new_lines = 0;
    if (o_.use_lines) {
      Announce(SfmStage::kLines);
      new_lines = TriangulateLines();
    }
    Announce(SfmStage::kAdjustment);
    Adjust(o_.local_iterations);
    RejectOutliers();
    Progress("registered view " + std::to_string(v) + " (" + std::to_string(order_.size()) + "/" +
             std::to_string(NumViews()) + "): " + std::to_string(num_inliers) + " PnP inliers, +" +
             std::to_string(new_points) + " points, +" + std::to_string(new_lines) + " lines");
    return true;
  }

  static void MarkOutlier(PointTrack* t, int view) {
    for (std::size_t i = 0; i < t->obs.size(); ++i)
      if (t->obs[i].first == view) t->outlier[i] = 1;
  }

  // Pose-only adjustment of view v against the fixed points (and lines when with_lines).
  void RefinePose(int v, bool with_lines) {
    ba::BundleAdjustmentData data;
    data.K = K_;
    data.T_w_c = {*pose_[v]};
    for (std::size_t t = 0; t < tracks_.size(); ++t) {
      const PointTrack& tr = tracks_[t];
      if (!tr.has_point) continue;
      for (std::size_t i = 0; i < tr.obs.size(); ++i) {
        if (tr.obs[i].first != v || tr.outlier[i]) continue;
        data.point_observations.push_back(
            {0, static_cast<int>(data.points_w.size()), views_[v].keypoints[tr.obs[i].second]});
        data.points_w.push_back(tr.p_w);
      }
    }
    if (with_lines) {
      for (const LineTrack& lt : line_tracks_) {
        if (!lt.has_line) continue;
        for (std::size_t i = 0; i < lt.obs.size(); ++i) {
          if (lt.obs[i].first != v || lt.outlier[i]) continue;
          const vision::Segment2d& s = views_[v].lines.segments[lt.obs[i].second];
          data.line_observations.push_back(
              {0, static_cast<int>(data.lines_w.size()), s.head<2>(), s.tail<2>()});
          data.lines_w.push_back(lt.L_w);
        }
      }
      if (!data.line_observations.empty()) ++line_refined_;
    }
    ba::BundleAdjustmentOptions options;
    options.num_fixed_poses = 0;
    options.point_sigma_px = o_.point_sigma_px;
    options.line_sigma_px = o_.line_sigma_px;
    options.refine_points = options.refine_lines = false;
    options.huber_threshold = o_.huber_px;
    options.max_iterations = 20;
    const ba::BundleAdjustmentResult r = ba::SolveBundleAdjustment(options, &data);
    if (r.success && data.T_w_c[0].translation().allFinite()) pose_[v] = data.T_w_c[0];
  }

  // ----- triangulation -----
  int TriangulatePoints() {
    PointTriangulationOptions options;
    options.min_parallax_deg = o_.min_triangulation_angle_deg;
    int added = 0;
    for (PointTrack& t : tracks_) {
      if (t.has_point || t.dead) continue;
      std::vector<SE3d> poses;
      std::vector<Eigen::Vector2d> uv;
      for (std::size_t i = 0; i < t.obs.size(); ++i) {
        const auto& [v, k] = t.obs[i];
        if (!pose_[v] || t.outlier[i]) continue;
        poses.push_back(*pose_[v]);
        uv.push_back(views_[v].keypoints[k]);
      }
      if (poses.size() < 2) continue;
      const PointTriangulationResult r = TriangulatePoint(K_, poses, uv, options);
      if (!r.ok() || r.final_rms_px > o_.max_reprojection_px) continue;
      t.p_w = r.p_w;
      t.has_point = true;
      ++added;
    }
    return added;
  }

  // Matches the lines of view v with those of the registered views it shares a verified pair
  // with (epipolar gating with the current poses) and joins them to line tracks.
  void MatchLines(int v) {
    if (views_[v].lines.size() == 0) return;
    std::vector<int> others;
    for (const VerifiedPair& p : pairs_) {
      const int r = p.a == v ? p.b : (p.b == v ? p.a : -1);
      if (r >= 0 && pose_[r] && views_[r].lines.size() > 0) others.push_back(r);
    }
    std::vector<vision::LineMatchResult> matches(others.size());
    ParallelFor(static_cast<int>(others.size()), o_.num_threads, [&](int k) {
      const int r = others[k];
      const SE3d T_v_r = pose_[v]->Inverse() * *pose_[r];
      const Eigen::Matrix3d E = Hat(T_v_r.translation()) * T_v_r.RotationMatrix();
      const Eigen::Matrix3d Kinv = K_.K().inverse();
      const Eigen::Matrix3d F_v_r = Kinv.transpose() * E * Kinv;
      matches[k] = vision::MatchLines(views_[r].lines, views_[v].lines, o_.line_matcher, F_v_r);
    });
    for (std::size_t k = 0; k < others.size(); ++k)
      for (const vision::LineMatch& lm : matches[k].matches) Join({others[k], lm.a}, {v, lm.b});
  }

  // The segments of view v just joined to tracks whose 3D line exists are checked against it
  // with the PnP pose: one further than max_reprojection_px is an outlier before it can enter the
  // pose refinement or the adjustment. Descriptor and epipolar gates cannot verify a match along
  // the epipolar direction, and where points are scarce a few wrong line matches would otherwise
  // pull the new pose (a 1.4 deg error on fountain-P11 with 385 points).
  void CheckNewLineObservations(int v) {
    for (LineTrack& t : line_tracks_) {
      if (!t.has_line) continue;
      for (std::size_t i = 0; i < t.obs.size(); ++i) {
        if (t.obs[i].first != v || t.outlier[i]) continue;
        const vision::Segment2d& seg = views_[v].lines.segments[t.obs[i].second];
        const auto err =
            LineReprojectionErrors(K_, {{*pose_[v], seg.head<2>(), seg.tail<2>()}}, t.L_w);
        if (!err || err->cwiseAbs().maxCoeff() > o_.max_reprojection_px) {
          t.outlier[i] = 1;
          ++rejected_lines_;
        }
      }
    }
  }

  bool TrackHasView(int t, int view) const {
    for (const Obs& o : line_tracks_[t].obs)
      if (o.first == view) return true;
    return false;
  }

  void AddToLineTrack(int t, const Obs& o) {
    line_tracks_[t].obs.push_back(o);
    line_tracks_[t].outlier.push_back(0);
    seg_track_[o.first][o.second] = t;
  }

  void Join(const Obs& a, const Obs& b) {
    int ta = seg_track_[a.first][a.second], tb = seg_track_[b.first][b.second];
    if (ta < 0 && tb < 0) {
      line_tracks_.emplace_back();
      const int t = static_cast<int>(line_tracks_.size()) - 1;
      AddToLineTrack(t, a);
      AddToLineTrack(t, b);
    } else if (tb < 0) {
      if (!TrackHasView(ta, b.first)) AddToLineTrack(ta, b);
    } else if (ta < 0) {
      if (!TrackHasView(tb, a.first)) AddToLineTrack(tb, a);
    } else if (ta != tb) {
      for (const Obs& o : line_tracks_[tb].obs)
        if (TrackHasView(ta, o.first)) return;  // the tracks disagree: keep both as they are
      if (line_tracks_[tb].has_line && !line_tracks_[ta].has_line) std::swap(ta, tb);
      for (const Obs& o : line_tracks_[tb].obs) AddToLineTrack(ta, o);
      line_tracks_[tb] = LineTrack();
      line_tracks_[tb].dead = true;
    }
  }

  std::vector<LineObservation> LineObservations(const LineTrack& t,
                                                std::vector<int>* index = nullptr) const {
    std::vector<LineObservation> obs;
    for (std::size_t i = 0; i < t.obs.size(); ++i) {
      const auto& [v, s] = t.obs[i];
      if (!pose_[v] || t.outlier[i]) continue;
      const vision::Segment2d& seg = views_[v].lines.segments[s];
      obs.push_back({*pose_[v], seg.head<2>(), seg.tail<2>()});
      if (index) index->push_back(static_cast<int>(i));
    }
    return obs;
  }

  int TriangulateLines() {
    int added = 0;
    for (LineTrack& t : line_tracks_) {
      if (t.has_line || t.dead) continue;
      const std::vector<LineObservation> obs = LineObservations(t);
      const int n = static_cast<int>(obs.size());
      if (n < std::max(2, o_.min_line_views) || n <= t.tried_views) continue;
      const LineTriangulationResult r = TriangulateLineRefined(K_, obs, o_.line_triangulation);
      if (!r.ok() || r.max_error_px > o_.max_reprojection_px) {
        t.tried_views = n;
        continue;
      }
      t.L_w = r.L_w;
      t.start_w = r.start_w;
      t.end_w = r.end_w;
      t.has_line = true;
      ++added;
    }
    return added;
  }

  // ----- adjustment -----
  void Adjust(int iterations) {
    ba::BundleAdjustmentData data;
    data.K = K_;
    std::vector<int> ba_index(NumViews(), -1);
    for (int v : order_) {
      ba_index[v] = static_cast<int>(data.T_w_c.size());
      data.T_w_c.push_back(*pose_[v]);
    }
    std::vector<int> point_of, line_of;
    for (std::size_t t = 0; t < tracks_.size(); ++t) {
      const PointTrack& tr = tracks_[t];
      if (!tr.has_point) continue;
      const int id = static_cast<int>(data.points_w.size());
      for (std::size_t i = 0; i < tr.obs.size(); ++i) {
        const auto& [v, k] = tr.obs[i];
        if (ba_index[v] < 0 || tr.outlier[i]) continue;
        data.point_observations.push_back({ba_index[v], id, views_[v].keypoints[k]});
      }
      data.points_w.push_back(tr.p_w);
      point_of.push_back(static_cast<int>(t));
    }
    for (std::size_t t = 0; t < line_tracks_.size(); ++t) {
      const LineTrack& lt = line_tracks_[t];
      if (!lt.has_line) continue;
      const int id = static_cast<int>(data.lines_w.size());
      for (std::size_t i = 0; i < lt.obs.size(); ++i) {
        const auto& [v, s] = lt.obs[i];
        if (ba_index[v] < 0 || lt.outlier[i]) continue;
        const vision::Segment2d& seg = views_[v].lines.segments[s];
        data.line_observations.push_back({ba_index[v], id, seg.head<2>(), seg.tail<2>()});
      }
      data.lines_w.push_back(lt.L_w);
      line_of.push_back(static_cast<int>(t));
    }
    ba::BundleAdjustmentOptions options;
    // Gauge: the first camera is held; the scale is left to Levenberg-Marquardt's damping
    // (holding the second camera too would freeze the essential-matrix pose of the initial pair
    // and bend every other camera to fit it).
    options.num_fixed_poses = 1;
    options.point_sigma_px = o_.point_sigma_px;
    options.line_sigma_px = o_.line_sigma_px;
    options.huber_threshold = o_.huber_px;
    options.max_iterations = iterations;
    options.num_threads = 1;  // see SfmOptions::num_threads
    options.function_tolerance = 1e-8;
    options.gradient_tolerance = 1e-10;
    options.parameter_tolerance = 1e-10;
    const ba::BundleAdjustmentResult r = ba::SolveBundleAdjustment(options, &data);
    ++adjustments_;
    if (!r.success) return;
    for (int v : order_) {
      const SE3d& T = data.T_w_c[ba_index[v]];
      if (T.translation().allFinite() && T.rotation().coeffs().allFinite()) pose_[v] = T;
    }
    for (std::size_t i = 0; i < point_of.size(); ++i)
      if (data.points_w[i].allFinite()) tracks_[point_of[i]].p_w = data.points_w[i];
    for (std::size_t i = 0; i < line_of.size(); ++i)
      if (data.lines_w[i].allFinite()) line_tracks_[line_of[i]].L_w = data.lines_w[i];
  }

  // Flags observations whose reprojection error exceeds max_reprojection_px; drops points and
  // lines left with too few observations. Returns the number of flagged observations.
  int RejectOutliers() {
    int rejected = 0;
    for (PointTrack& t : tracks_) {
      if (!t.has_point) continue;
      int good = 0;
      for (std::size_t i = 0; i < t.obs.size(); ++i) {
        const auto& [v, k] = t.obs[i];
        if (!pose_[v] || t.outlier[i]) continue;
        const auto uv = ProjectPoint(K_, *pose_[v], t.p_w);
        if (!uv || (*uv - views_[v].keypoints[k]).norm() > o_.max_reprojection_px) {
          t.outlier[i] = 1;
          ++rejected;
          ++rejected_points_;
        } else {
          ++good;
        }
      }
      if (good < 2) t.has_point = false, t.dead = true;
    }
    for (LineTrack& t : line_tracks_) {
      if (!t.has_line) continue;
      std::vector<int> index;
      const std::vector<LineObservation> obs = LineObservations(t, &index);
      const auto err = LineReprojectionErrors(K_, obs, t.L_w);
      int good = 0;
      for (std::size_t i = 0; i < obs.size(); ++i) {
        if (!err || std::max(std::abs((*err)(2 * i)), std::abs((*err)(2 * i + 1))) >
                        o_.max_reprojection_px) {
          t.outlier[index[i]] = 1;
          ++rejected;
          ++rejected_lines_;
        } else {
          ++good;
        }
      }
      if (good < 2) t.has_line = false, t.dead = true;
    }
    return rejected;
  }

  // The 3D segment of each line: the extent along d of the endpoints seen in every view.
  void UpdateLineExtents() {
    for (LineTrack& t : line_tracks_) {
      if (!t.has_line) continue;
      const auto L = NormalizeLineDirection(t.L_w);
      if (!L) continue;
      t.L_w = *L;
      const Eigen::Vector3d d = L->tail<3>();
      const Eigen::Vector3d p0 = d.cross(L->head<3>());  // closest point to the origin
      double lo = 1e300, hi = -1e300;
      for (const LineObservation& o : LineObservations(t)) {
        const auto e = SegmentEndpointsOnLine(K_, o, *L);
        if (!e || e->start_depth <= 0 || e->end_depth <= 0) continue;
        for (const Eigen::Vector3d& x : {e->start_w, e->end_w}) {
          lo = std::min(lo, d.dot(x - p0));
          hi = std::max(hi, d.dot(x - p0));
        }
      }
      if (lo < hi) t.start_w = p0 + lo * d, t.end_w = p0 + hi * d;
    }
  }

  SfmResult Finish(SfmResult r) {
    r.T_w_c = pose_;
    r.view_status = status_;
    double point_err = 0.0, line_err = 0.0;
    for (const PointTrack& t : tracks_) {
      if (!t.has_point) continue;
      SfmPoint p;
      p.p_w = t.p_w;
      for (std::size_t i = 0; i < t.obs.size(); ++i) {
        const auto& [v, k] = t.obs[i];
        if (!pose_[v] || t.outlier[i]) continue;
        const auto uv = ProjectPoint(K_, *pose_[v], t.p_w);
        if (!uv) continue;
        point_err += (*uv - views_[v].keypoints[k]).norm();
        p.observations.push_back(t.obs[i]);
      }
      r.stats.point_observations += static_cast<int>(p.observations.size());
      r.points.push_back(std::move(p));
    }
    for (const LineTrack& t : line_tracks_) {
      if (!t.has_line) continue;
      SfmLine l;
      l.L_w = t.L_w;
      l.start_w = t.start_w;
      l.end_w = t.end_w;
      std::vector<int> index;
      const auto obs = LineObservations(t, &index);
      const auto err = LineReprojectionErrors(K_, obs, t.L_w);
      if (!err) continue;
      line_err += err->cwiseAbs().sum();
      for (int i : index) l.observations.push_back(t.obs[i]);
      r.stats.line_observations += static_cast<int>(l.observations.size());
      r.lines.push_back(std::move(l));
    }
    r.stats.registered = static_cast<int>(order_.size());
    r.stats.points = static_cast<int>(r.points.size());
    r.stats.lines = static_cast<int>(r.lines.size());
    if (r.stats.point_observations > 0)
      r.stats.mean_point_error_px = point_err / r.stats.point_observations;
    if (r.stats.line_observations > 0)
      r.stats.mean_line_error_px = line_err / (2.0 * r.stats.line_observations);
    r.stats.init_a = init_a_;
    r.stats.init_b = init_b_;
    r.stats.rejected_point_observations = rejected_points_;
    r.stats.rejected_line_observations = rejected_lines_;
    r.stats.adjustments = adjustments_;
    r.stats.line_refined_registrations = line_refined_;
    return r;
  }

  const PinholeIntrinsics K_;
  const std::vector<ViewFeatures>& views_;
  const SfmOptions o_;
  const SfmObserver& observer_;
  const SfmProgress& progress_;

  std::vector<std::optional<SE3d>> pose_;
  std::vector<std::string> status_;
  std::vector<int> failed_count_;
  std::vector<int> order_;  // registration order; the first two are the initial pair
  std::vector<VerifiedPair> pairs_;
  std::vector<std::vector<int>> kp_track_, seg_track_;
  std::vector<PointTrack> tracks_;
  std::vector<LineTrack> line_tracks_;
  int point_tracks_total_ = 0;
  int init_a_ = -1, init_b_ = -1;
  int rejected_points_ = 0, rejected_lines_ = 0, adjustments_ = 0, line_refined_ = 0;
};

}  // namespace

SfmResult Reconstruct(const PinholeIntrinsics& K, const std::vector<ViewFeatures>& views,
                      const SfmOptions& options, const SfmObserver& observer,
                      const SfmProgress& progress) {
  if (!K.IsValid()) {
    SfmResult r;
    r.message = "invalid intrinsics";
    r.T_w_c.assign(views.size(), std::nullopt);
    r.view_status.assign(views.size(), "not registered");
    r.stats.views = static_cast<int>(views.size());
    return r;
  }
  return Reconstruction(K, views, options, observer, progress).Run();
}

}  // namespace sfm
}  // namespace plucker
