// Accuracy of estimated structure and poses against ground truth (simulation), for tests, the
// demo and the benchmarks. The Compare* functions apply no alignment; CompareToGroundTruth can
// first align the estimate (a bundle adjustment fixes its gauge only as well as its fixed poses
// do: the scale of a solve fixed by two nearby poses drifts, and shows as metres of structure
// error that the solve could not remove).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "plucker/ba/bundle_adjustment.h"
#include "plucker/eval/alignment.h"
#include "plucker/eval/statistics.h"
#include "plucker/geometry/plucker_line.h"
#include "plucker/geometry/se3.h"

namespace plucker {
namespace ba {

using ErrorStats = eval::ErrorStatistics;

struct PoseAccuracy {
  ErrorStats rotation_deg;   // angle of R_gt^T R_est
  ErrorStats translation_m;  // |t_est - t_gt|
};
PoseAccuracy ComparePoses(const std::vector<SE3d>& estimate, const std::vector<SE3d>& gt);

// Euclidean distance of each point to its ground truth.
ErrorStats ComparePoints(const std::vector<Eigen::Vector3d>& estimate,
                         const std::vector<Eigen::Vector3d>& gt);

struct LineAccuracy {
  ErrorStats direction_deg;  // angle between the directions (sign-free)
  ErrorStats distance_m;     // distance between the estimated line and the true segment's two
                             // endpoints, the larger of the two (0 when the lines coincide on
                             // the segment)
  int invalid = 0;           // estimated lines that are not valid Plücker lines
};
struct WorldSegment {
  Eigen::Vector3d a_w, b_w;
};
LineAccuracy CompareLines(const std::vector<Line6d>& estimate,
                          const std::vector<WorldSegment>& segments_gt);

// A world line mapped by the similarity S (points p -> s R p + t): the line through the mapped
// points, n' = s R n + t x (R d), d' = R d.
Line6d ApplySimilarity(const eval::Similarity& S, const Line6d& L);

// Accuracy of a whole reconstruction. `scale` is that of the alignment (1 unless kSim3).
struct ProblemAccuracy {
  PoseAccuracy poses;
  ErrorStats points_m;
  LineAccuracy lines;
  double scale = 1.0;
};

// Compares `state` with the ground truth after `alignment` of the estimated camera centres onto
// the true ones (eval::AlignTrajectory), the same similarity applied to the poses, points and
// lines alike. kNone compares in the gauge of the solve. Throws std::invalid_argument when the
// alignment is undefined (fewer than two distinct camera centres for kSim3, sizes differ).
ProblemAccuracy CompareToGroundTruth(const BundleAdjustmentData& state,
                                     const std::vector<SE3d>& T_w_c_gt,
                                     const std::vector<Eigen::Vector3d>& points_gt,
                                     const std::vector<WorldSegment>& segments_gt,
                                     eval::AlignmentMode alignment);

}  // namespace ba
}  // namespace plucker
