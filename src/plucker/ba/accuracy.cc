#include "plucker/ba/accuracy.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace plucker {
namespace ba {

PoseAccuracy ComparePoses(const std::vector<SE3d>& estimate, const std::vector<SE3d>& truth) {
  std::vector<double> rot, trans;
  const std::size_t n = std::min(estimate.size(), truth.size());
  for (std::size_t i = 0; i < n; ++i) {
    rot.push_back(LogSO3<double>(truth[i].rotation().conjugate() * estimate[i].rotation()).norm() *
                  180.0 / M_PI);
    trans.push_back((estimate[i].translation() - truth[i].translation()).norm());
  }
  return {eval::ComputeStatistics(rot), eval::ComputeStatistics(trans)};
}

ErrorStats ComparePoints(const std::vector<Eigen::Vector3d>& estimate,
                         const std::vector<Eigen::Vector3d>& truth) {
  std::vector<double> e;
  const std::size_t n = std::min(estimate.size(), truth.size());
  for (std::size_t i = 0; i < n; ++i) e.push_back((estimate[i] - truth[i]).norm());
  return eval::ComputeStatistics(e);
}

LineAccuracy CompareLines(const std::vector<Line6d>& estimate,
                          const std::vector<SegmentTruth>& truth) {
  LineAccuracy acc;
  std::vector<double> dir, dist;
  const std::size_t n = std::min(estimate.size(), truth.size());
  for (std::size_t i = 0; i < n; ++i) {
    const std::optional<double> da = PointLineDistance(estimate[i], truth[i].a_w);
    const std::optional<double> db = PointLineDistance(estimate[i], truth[i].b_w);
    const Eigen::Vector3d d_est = estimate[i].tail<3>();
    const Eigen::Vector3d d_gt = truth[i].b_w - truth[i].a_w;
    if (!da || !db || d_est.norm() == 0.0 || d_gt.norm() == 0.0) {
      ++acc.invalid;
      continue;
    }
    const double c = std::min(1.0, std::abs(d_est.normalized().dot(d_gt.normalized())));
    dir.push_back(std::acos(c) * 180.0 / M_PI);
    dist.push_back(std::max(*da, *db));
  }
  acc.direction_deg = eval::ComputeStatistics(dir);
  acc.distance_m = eval::ComputeStatistics(dist);
  return acc;
}

}  // namespace ba
}  // namespace plucker
