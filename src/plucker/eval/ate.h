// Absolute trajectory error: position differences between associated poses after aligning the
// estimate to the ground truth (eval/alignment.h).
//   e_i = | p_gt_i - (s R p_est_i + t) |                          (metres)
//   rotation error of pose i: angle(R_gt_i^T R R_est_i)          (degrees, reported as well)
#pragma once

#include <vector>

#include "plucker/eval/alignment.h"
#include "plucker/eval/statistics.h"
#include "plucker/geometry/se3.h"

namespace plucker {
namespace eval {

struct AteOptions {
  AlignmentMode align = AlignmentMode::kSE3;  // kSim3 for monocular (scale-free) estimates
};

struct AteResult {
  AlignmentMode align = AlignmentMode::kSE3;
  Similarity alignment;                 // est -> gt
  bool roll_from_orientations = false;  // collinear positions: see AlignTrajectory
  ErrorStatistics translation_m;        // the ATE (its rmse is the usual single number)
  ErrorStatistics rotation_deg;
  std::vector<double> translation_errors;   // per pose, metres
  std::vector<double> rotation_errors_deg;  // per pose
  std::vector<double> distance;             // ground-truth path length at each pose, metres
  std::vector<SE3d> aligned_estimate;       // S * est_i, for plots
};

// gt and est are associated element-wise (eval/association.h). Throws std::invalid_argument if
// the sizes differ, are zero, or the alignment is undefined (Sim(3) with a single point).
AteResult ComputeAte(const std::vector<SE3d>& gt, const std::vector<SE3d>& est,
                     const AteOptions& options = {});

// Rotation angle of R in radians, in [0, pi], computed stably from the quaternion.
double RotationAngle(const Eigen::Quaterniond& q);

}  // namespace eval
}  // namespace plucker
