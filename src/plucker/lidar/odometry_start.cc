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
// the normal registration from its start pose (below); the best start pose is returned with its
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
  std::vector<double> matches, cost;
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
  }
  const double most = matches.empty() ? 0.0 : *std::max_element(matches.begin(), matches.end());
  int best = -1;
  for (std::size_t k = 0; k < matches.size(); ++k) {
    if (matches[k] >= 0.9 * most && (best < 0 || cost[k] < cost[best])) best = static_cast<int>(k);
  }
  if (best < 0) return RegisterStart(observer, features, result);
  *result = starts[best];
  result->start_rounds = start_rounds;  // all candidates' rounds: the work done
  return poses[best];
}

}  // namespace lidar
}  // namespace plucker
