#include "plucker/eval/rpe.h"

#include <cmath>
#include <stdexcept>

#include "plucker/eval/ate.h"

namespace plucker {
namespace eval {

RpeResult ComputeRpe(const std::vector<SE3d>& gt, const std::vector<SE3d>& est,
                     const RpeOptions& options) {
  if (gt.size() != est.size() || gt.empty()) {
    throw std::invalid_argument("RPE needs equally many (> 0) associated poses; got " +
                                std::to_string(gt.size()) + " and " + std::to_string(est.size()));
  }
  const bool frames = options.unit == DeltaUnit::kFrames;
  if (!std::isfinite(options.delta) || options.delta <= 0.0 ||
      (frames && options.delta != std::floor(options.delta))) {
    throw std::invalid_argument("the RPE delta must be a positive " +
                                std::string(frames ? "whole number of frames" : "distance"));
  }
  const std::vector<Eigen::Vector3d> p_gt = Positions(gt);
  const std::optional<TrajectoryAlignment> alignment = AlignTrajectory(est, gt, options.align);
  if (!alignment) {
    throw std::invalid_argument("cannot align with " + AlignmentName(options.align) +
                                ": the estimate positions all coincide (scale undefined)");
  }
  RpeResult r;
  r.options = options;
  const Similarity* S = &alignment->S;
  r.alignment = *S;
  r.roll_from_orientations = alignment->roll_from_orientations;
  for (const SE3d& T : est) r.aligned_estimate.push_back(S->Apply(T));
  const std::vector<double> dist = PathDistances(p_gt);
  const int n = static_cast<int>(gt.size());
  int j = 0;
  for (int i = 0; i < n; ++i) {
    if (frames) {
      if (options.delta >= n - i) break;
      j = i + static_cast<int>(options.delta);
    } else {
      j = std::max(j, i + 1);
      while (j < n && dist[j] - dist[i] < options.delta) ++j;
      if (j >= n) break;
    }
    const SE3d ij_gt = gt[i].Inverse() * gt[j];
    const SE3d est_ij = r.aligned_estimate[i].Inverse() * r.aligned_estimate[j];
    const SE3d E = ij_gt.Inverse() * est_ij;
    r.first.push_back(i);
    r.last.push_back(j);
    r.translation_errors.push_back(E.translation().norm());
    r.rotation_errors_deg.push_back(RotationAngle(E.rotation()) * 180.0 / M_PI);
    r.distance.push_back(dist[i]);
  }
  if (r.first.empty()) {
    throw std::invalid_argument(
        frames ? "no frame pair " + std::to_string(static_cast<int>(options.delta)) +
                     " frames apart in a sequence of " + std::to_string(n) + " poses"
               : "no frame pair " + std::to_string(options.delta) +
                     " m apart: the ground-truth path is " + std::to_string(dist.back()) + " m");
  }
  r.translation_m = ComputeStatistics(r.translation_errors);
  r.rotation_deg = ComputeStatistics(r.rotation_errors_deg);
  return r;
}

}  // namespace eval
}  // namespace plucker
