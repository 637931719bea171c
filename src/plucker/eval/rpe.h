// Relative pose error over a fixed delta (frames or metres of ground-truth path):
//   for each start i with end j = i + delta (frames), or j = the first frame whose ground-truth
//   path distance from i is >= delta (metres):
//     E_ij = inv(inv(gt_i) gt_j) * (inv(est_i) est_j)
//   translation error |t(E_ij)| (m) and rotation error angle(R(E_ij)) (deg).
// Relative motions do not change under an SE(3) alignment; a Sim(3) alignment (options.align)
// rescales the estimate's translations first, which matters for monocular estimates.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "plucker/eval/alignment.h"
#include "plucker/eval/statistics.h"
#include "plucker/geometry/se3.h"

namespace plucker {
namespace eval {

enum class DeltaUnit { kFrames, kMeters };

struct RpeOptions {
  double delta = 1.0;  // frames (an integer >= 1) or metres (> 0)
  DeltaUnit unit = DeltaUnit::kFrames;
  AlignmentMode align = AlignmentMode::kNone;
};

struct RpeResult {
  RpeOptions options;
  Similarity alignment;                 // est -> gt (identity for kNone)
  bool roll_from_orientations = false;  // collinear positions: see AlignTrajectory
  ErrorStatistics translation_m;
  ErrorStatistics rotation_deg;
  std::vector<int> first, last;             // the frame pairs
  std::vector<double> translation_errors;   // per pair, metres
  std::vector<double> rotation_errors_deg;  // per pair
  std::vector<double> distance;             // ground-truth path length at each pair's start
  std::vector<SE3d> aligned_estimate;
};

// gt and est are associated element-wise. Throws std::invalid_argument for mismatched sizes, a
// bad delta, an undefined alignment, or when no pair fits (e.g. delta >= the sequence length;
// the message says so).
RpeResult ComputeRpe(const std::vector<SE3d>& gt, const std::vector<SE3d>& est,
                     const RpeOptions& options = {});

}  // namespace eval
}  // namespace plucker
