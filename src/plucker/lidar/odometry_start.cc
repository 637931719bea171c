// The wide start of LidarOdometry (LidarOdometryOptions::start_max_speed): the second registered
// scan after a gap, before any motion is known.
#include <algorithm>
#include <cmath>

#include "plucker/lidar/odometry.h"

namespace plucker {
namespace lidar {

// The start path (RegisterStart) from forward offsets of the prediction (result->T_w_s) every
// start_distance / 2 up to start_max_speed * periods * scan_period; each candidate is scored by
// the normal registration from its start pose (plane + edge correspondences of its last round,
// the points within the normal search and residual limits), the best start pose is returned with
// its start statistics in *result. The start stages alone reach ~3-4 m (docs/results/
// lidar-start.md); a gap of n scans at speed v needs (n + 1) v / rate.
SE3d LidarOdometry::RegisterWideStart(double periods, const StageObserver& observer,
                                      ScanFeatures* features, FrameResult* result) {
  const LidarOdometryOptions& o = options_;
  const double reach = o.start_max_speed * periods * o.features.scan_period;
  const double step = 0.5 * o.start_distance;
  const int candidates = o.start_max_speed > 0.0
                             ? std::clamp(static_cast<int>(std::ceil(reach / step)) + 1, 1, 64)
                             : 1;
  const SE3d T_w_s_pred = result->T_w_s;
  const FrameResult initial = *result;
  FrameResult best;
  SE3d T_w_s_best = T_w_s_pred;
  int best_score = -1, start_rounds = 0;
  for (int k = 0; k < candidates; ++k) {
    FrameResult r = initial;
    r.T_w_s = T_w_s_pred * SE3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(k * step, 0, 0));
    const SE3d T_w_s_start = RegisterStart(observer, features, &r);
    start_rounds += r.start_rounds;
    if (candidates == 1) return T_w_s_start;
    FrameResult scored = r;
    if (!RunRounds(o, edge_map_, plane_map_, T_w_s_start, true, observer, features, &scored))
      continue;
    start_rounds += scored.association_rounds;
    const int score = scored.plane_correspondences + scored.edge_correspondences;
    if (score > best_score) {
      best_score = score;
      best = r;
      T_w_s_best = T_w_s_start;
    }
  }
  if (best_score < 0) return RegisterStart(observer, features, result);
  *result = best;
  result->start_rounds = start_rounds;  // all candidates' rounds: the work done
  return T_w_s_best;
}

}  // namespace lidar
}  // namespace plucker
