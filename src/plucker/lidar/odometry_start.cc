// The wide start of LidarOdometry (LidarOdometryOptions::start_max_speed): the second registered
// scan after a gap, before any motion is known.
#include <algorithm>
#include <cmath>
#include <vector>

#include "plucker/lidar/odometry.h"

namespace plucker {
namespace lidar {

// The start path (RegisterStart) from forward offsets of the prediction (result->T_w_s) every
// start_distance / 2 up to start_max_speed * periods * scan_period; each candidate is scored by
// the normal registration from its start pose (below: matches, cost per match, then the
// information along the weakest translation); the best start pose is returned with its
// start statistics in *result. The start stages alone reach ~3-4 m (docs/results/
// lidar-start.md); a gap of n scans at speed v needs (n + 1) v / rate.
SE3d LidarOdometry::RegisterWideStart(double periods, const StageObserver& observer,
                                      ScanFeatures* features, FrameResult* result) {
  const LidarOdometryOptions& o = options_;
  const double reach = o.start_max_speed * periods * o.features.scan_period;
  const double step = 0.5 * o.start_distance;
  const int candidates = o.start_max_speed > 0.0
                             ? std::clamp(static_cast<int>(std::ceil(reach / step)) + 1, 1, 64)
                             : 1;
  if (candidates == 1) return RegisterStart(observer, features, result);
  const SE3d T_w_s_pred = result->T_w_s;
  const FrameResult initial = *result;
  int start_rounds = 0;
  // Scores: the matches of each candidate's normal registration and its cost per match. Where
  // the cross-section repeats (a straight street), wrong offsets match as many points (up to the
  // max_*_points caps): of the candidates within 10 % of the most matches, the lowest cost per
  // match wins (the misaligned poles and corners cost more).
  std::vector<FrameResult> starts;
  std::vector<SE3d> poses;
  std::vector<double> matches, cost, weakest;
  for (int k = 0; k < candidates; ++k) {
    FrameResult r = initial;
    r.T_w_s = T_w_s_pred * SE3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(k * step, 0, 0));
    const SE3d T_w_s_start = RegisterStart(observer, features, &r);
    start_rounds += r.start_rounds;
    FrameResult scored = r;
    if (!RunRounds(o, edge_map_, plane_map_, T_w_s_start, true, observer, features, &scored))
      continue;
    start_rounds += scored.association_rounds;
    const int n = scored.plane_correspondences + scored.edge_correspondences;
    starts.push_back(r);
    poses.push_back(T_w_s_start);
    matches.push_back(n);
    cost.push_back(scored.final_cost / std::max(n, 1));
    weakest.push_back(scored.degeneracy.translation_information(0));
  }
  const double most = matches.empty() ? 0.0 : *std::max_element(matches.begin(), matches.end());
  int best = -1;
  for (std::size_t k = 0; k < matches.size(); ++k) {
    if (matches[k] >= 0.9 * most && (best < 0 || cost[k] < cost[best])) best = static_cast<int>(k);
  }
  if (best < 0) return RegisterStart(observer, features, result);
  // The registration's own information: a wrong offset on a straight street slides along the
  // walls and the ground (its weakest translation, per row, 1-4 in the runs of docs/results/
  // lidar.md) where the right one also matches the structures across the road (6-20). The
  // candidate whose weakest translation is clearly better constrained, kClearly times the
  // chosen one's, replaces it (a 12 m gap against the one-scan map matches fewer points at the
  // right offset than at offset 0: the rule above alone picks 0).
  constexpr double kClearly = 3.0;
  const int firm =
      static_cast<int>(std::max_element(weakest.begin(), weakest.end()) - weakest.begin());
  if (weakest[firm] > kClearly * weakest[best]) best = firm;
  wide_start_periods_ = periods;
  T_w_s_wide_from_ = T_w_s_pred;
  *result = starts[best];
  result->start_rounds = start_rounds;  // all candidates' rounds: the work done
  return poses[best];
}

// The prediction for the scan after a wide start: the motion found over the gap, T_w_s_from^-1
// T_w_s, spread over the periods it spans (a constant twist, PredictPoseAt). Without it, after
// skipped scans (their slots hold the start pose: no velocity was known) the constant-velocity
// step would be the whole gap: 12 m per scan after a 12 m gap, and the next pair erred 224 cm.
// Returns false (and *T_w_s_pred as given) when the last pose did not come from a wide start.
bool LidarOdometry::PredictAfterWideStart(double stamp, SE3d* T_w_s_pred) {
  const double periods = wide_start_periods_;
  wide_start_periods_ = 0.0;
  if (!(periods > 1.5) || poses_.empty() || !options_.constant_velocity) return false;
  const double period = options_.features.scan_period, last = stamps_.back();
  const double elapsed = stamp > last && last > 0.0 ? stamp - last : period;
  int steps = 1;
  *T_w_s_pred = PredictPoseAt({T_w_s_wide_from_, poses_.back()}, {0.0, periods * period},
                              periods * period + elapsed, true, &steps);
  return true;
}

}  // namespace lidar
}  // namespace plucker
