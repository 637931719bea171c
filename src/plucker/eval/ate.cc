#include "plucker/eval/ate.h"

#include <cmath>
#include <stdexcept>

namespace plucker {
namespace eval {

double RotationAngle(const Eigen::Quaterniond& q) {
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

AteResult ComputeAte(const std::vector<SE3d>& gt, const std::vector<SE3d>& est,
                     const AteOptions& options) {
  if (gt.size() != est.size() || gt.empty()) {
    throw std::invalid_argument("ATE needs equally many (> 0) associated poses; got " +
                                std::to_string(gt.size()) + " and " + std::to_string(est.size()));
  }
  const std::vector<Eigen::Vector3d> p_gt = Positions(gt);
  const std::optional<TrajectoryAlignment> alignment = AlignTrajectory(est, gt, options.align);
  if (!alignment) {
    throw std::invalid_argument("cannot align with " + AlignmentName(options.align) +
                                ": the estimate positions all coincide (scale undefined)");
  }
  AteResult r;
  r.align = options.align;
  const Similarity* S = &alignment->S;
  r.alignment = *S;
  r.roll_from_orientations = alignment->roll_from_orientations;
  r.distance = PathDistances(p_gt);
  r.aligned_estimate.reserve(est.size());
  for (std::size_t i = 0; i < est.size(); ++i) {
    const SE3d aligned = S->Apply(est[i]);
    r.aligned_estimate.push_back(aligned);
    r.translation_errors.push_back((p_gt[i] - aligned.translation()).norm());
    r.rotation_errors_deg.push_back(
        RotationAngle(gt[i].rotation().conjugate() * aligned.rotation()) * 180.0 / M_PI);
  }
  r.translation_m = ComputeStatistics(r.translation_errors);
  r.rotation_deg = ComputeStatistics(r.rotation_errors_deg);
  return r;
}

}  // namespace eval
}  // namespace plucker
