#include "plucker/eval/association.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace plucker {
namespace eval {

AssociatedTrajectories AssociateByIndex(const std::vector<SE3d>& gt, const std::vector<SE3d>& est) {
  if (gt.size() != est.size()) {
    throw std::invalid_argument("the ground truth has " + std::to_string(gt.size()) +
                                " poses but the estimate has " + std::to_string(est.size()) +
                                " (frame-by-frame comparison needs equal counts)");
  }
  if (gt.empty()) throw std::invalid_argument("no poses to compare");
  AssociatedTrajectories a;
  a.gt = gt;
  a.est = est;
  a.count_gt = a.count_est = static_cast<int>(gt.size());
  for (int i = 0; i < a.count_gt; ++i) {
    a.index_gt.push_back(i);
    a.index_est.push_back(i);
  }
  return a;
}

AssociatedTrajectories AssociateByTime(const std::vector<double>& times_gt,
                                       const std::vector<SE3d>& gt,
                                       const std::vector<double>& times_est,
                                       const std::vector<SE3d>& est,
                                       const AssociationOptions& options) {
  if (times_gt.size() != gt.size() || times_est.size() != est.size()) {
    throw std::invalid_argument("each pose needs a timestamp");
  }
  if (!(options.max_time_difference >= 0.0)) {
    throw std::invalid_argument("the time tolerance must be >= 0");
  }
  if (!std::is_sorted(times_gt.begin(), times_gt.end()) ||
      !std::is_sorted(times_est.begin(), times_est.end())) {
    throw std::invalid_argument("timestamps must be non-decreasing");
  }
  // Nearest ground-truth time of each estimate time; then each ground-truth pose keeps only the
  // closest estimate that chose it.
  const int n_gt = static_cast<int>(gt.size());
  std::vector<int> best_est(n_gt, -1);
  std::vector<double> best_dt(n_gt, 0.0);
  for (int j = 0; j < static_cast<int>(est.size()); ++j) {
    const auto it = std::lower_bound(times_gt.begin(), times_gt.end(), times_est[j]);
    int i = static_cast<int>(it - times_gt.begin());
    if (i == n_gt || (i > 0 && times_est[j] - times_gt[i - 1] <= times_gt[i] - times_est[j])) {
      --i;
    }
    if (i < 0) continue;
    const double dt = std::abs(times_gt[i] - times_est[j]);
    if (dt > options.max_time_difference) continue;
    if (best_est[i] < 0 || dt < best_dt[i]) {
      best_est[i] = j;
      best_dt[i] = dt;
    }
  }
  AssociatedTrajectories a;
  a.by_time = true;
  a.count_gt = n_gt;
  a.count_est = static_cast<int>(est.size());
  for (int i = 0; i < n_gt; ++i) {
    if (best_est[i] < 0) continue;
    a.gt.push_back(gt[i]);
    a.est.push_back(est[best_est[i]]);
    a.times.push_back(times_gt[i]);
    a.index_gt.push_back(i);
    a.index_est.push_back(best_est[i]);
    a.max_time_difference_used = std::max(a.max_time_difference_used, best_dt[i]);
  }
  if (a.gt.empty()) {
    throw std::invalid_argument(
        "no estimate timestamp is within " + std::to_string(options.max_time_difference) +
        " s of a ground-truth timestamp (ground truth " +
        (times_gt.empty()
             ? std::string("empty")
             : std::to_string(times_gt.front()) + ".." + std::to_string(times_gt.back())) +
        ", estimate " +
        (times_est.empty()
             ? std::string("empty")
             : std::to_string(times_est.front()) + ".." + std::to_string(times_est.back())) +
        ")");
  }
  return a;
}

}  // namespace eval
}  // namespace plucker
