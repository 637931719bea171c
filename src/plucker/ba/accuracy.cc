#include "plucker/ba/accuracy.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace plucker {
namespace ba {

PoseAccuracy ComparePoses(const std::vector<SE3d>& estimate, const std::vector<SE3d>& gt) {
  std::vector<double> rot, trans;
  const std::size_t n = std::min(estimate.size(), gt.size());
  for (std::size_t i = 0; i < n; ++i) {
    rot.push_back(LogSO3<double>(gt[i].rotation().conjugate() * estimate[i].rotation()).norm() *
                  180.0 / M_PI);
    trans.push_back((estimate[i].translation() - gt[i].translation()).norm());
  }
  return {eval::ComputeStatistics(rot), eval::ComputeStatistics(trans)};
}

ErrorStats ComparePoints(const std::vector<Eigen::Vector3d>& estimate,
                         const std::vector<Eigen::Vector3d>& gt) {
  std::vector<double> e;
  const std::size_t n = std::min(estimate.size(), gt.size());
  for (std::size_t i = 0; i < n; ++i) e.push_back((estimate[i] - gt[i]).norm());
  return eval::ComputeStatistics(e);
}

LineAccuracy CompareLines(const std::vector<Line6d>& estimate,
                          const std::vector<WorldSegment>& segments_gt) {
  LineAccuracy acc;
  std::vector<double> dir, dist;
  const std::size_t n = std::min(estimate.size(), segments_gt.size());
  for (std::size_t i = 0; i < n; ++i) {
    const WorldSegment& gt = segments_gt[i];
    const std::optional<double> da = PointLineDistance(estimate[i], gt.a_w);
    const std::optional<double> db = PointLineDistance(estimate[i], gt.b_w);
    const Eigen::Vector3d d_est = estimate[i].tail<3>();
    const Eigen::Vector3d d_gt = gt.b_w - gt.a_w;
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

Line6d ApplySimilarity(const eval::Similarity& S, const Line6d& L) {
  const Eigen::Vector3d d = S.R * L.tail<3>();
  Line6d out;
  out << S.scale * (S.R * L.head<3>()) + S.t.cross(d), d;
  return out;
}

ProblemAccuracy CompareToGroundTruth(const BundleAdjustmentData& state,
                                     const std::vector<SE3d>& T_w_c_gt,
                                     const std::vector<Eigen::Vector3d>& points_gt,
                                     const std::vector<WorldSegment>& segments_gt,
                                     eval::AlignmentMode alignment) {
  const std::optional<eval::TrajectoryAlignment> fit =
      eval::AlignTrajectory(state.T_w_c, T_w_c_gt, alignment);
  if (!fit) {
    throw std::invalid_argument("cannot align " + std::to_string(state.T_w_c.size()) +
                                " estimated cameras to " + std::to_string(T_w_c_gt.size()) +
                                " true ones (" + eval::AlignmentName(alignment) + ")");
  }
  const eval::Similarity& S = fit->S;
  std::vector<SE3d> poses;
  std::vector<Eigen::Vector3d> points;
  std::vector<Line6d> lines;
  for (const SE3d& T_w_c : state.T_w_c) poses.push_back(S.Apply(T_w_c));
  for (const Eigen::Vector3d& p_w : state.points_w) points.push_back(S * p_w);
  for (const Line6d& L_w : state.lines_w) lines.push_back(ApplySimilarity(S, L_w));
  ProblemAccuracy a;
  a.poses = ComparePoses(poses, T_w_c_gt);
  a.points_m = ComparePoints(points, points_gt);
  a.lines = CompareLines(lines, segments_gt);
  a.scale = S.scale;
  return a;
}

}  // namespace ba
}  // namespace plucker
