// Accuracy of estimated structure and poses against ground truth (simulation), for tests, the
// demo and the benchmarks. No alignment is applied: callers compare in the gauge they fixed.
#pragma once

#include <Eigen/Core>
#include <vector>

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
PoseAccuracy ComparePoses(const std::vector<SE3d>& estimate, const std::vector<SE3d>& truth);

// Euclidean distance of each point to its ground truth.
ErrorStats ComparePoints(const std::vector<Eigen::Vector3d>& estimate,
                         const std::vector<Eigen::Vector3d>& truth);

struct LineAccuracy {
  ErrorStats direction_deg;  // angle between the directions (sign-free)
  ErrorStats distance_m;     // distance between the estimated line and the truth's two endpoints,
                             // the larger of the two (0 when the lines coincide on the segment)
  int invalid = 0;           // estimated lines that are not valid Plücker lines
};
struct SegmentTruth {
  Eigen::Vector3d a_w, b_w;
};
LineAccuracy CompareLines(const std::vector<Line6d>& estimate,
                          const std::vector<SegmentTruth>& truth);

}  // namespace ba
}  // namespace plucker
