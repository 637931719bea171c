// Pairing the poses of a ground truth and an estimate before a metric compares them.
//
// By index (KITTI: one pose a frame in both files): the sizes must be equal; a mismatch is an
// error, never a silent truncation. By time (TUM): each estimate pose is paired with the ground
// truth pose of nearest timestamp if within `max_time_difference`; each ground-truth pose is used
// at most once (the closer candidate wins); the counts of paired and unpaired poses are reported.
#pragma once

#include <string>
#include <vector>

#include "plucker/geometry/se3.h"

namespace plucker {
namespace eval {

struct AssociationOptions {
  double max_time_difference = 0.02;  // seconds (TUM associate.py uses 0.02)
};

struct AssociatedTrajectories {
  std::vector<SE3d> gt;  // T_ref_frame, paired element-wise with est
  std::vector<SE3d> est;
  std::vector<double> times;   // the ground-truth time of each pair; empty when by index
  std::vector<int> index_gt;   // index of each pair in the input ground truth
  std::vector<int> index_est;  // index of each pair in the input estimate
  int count_gt = 0;            // input sizes
  int count_est = 0;
  bool by_time = false;
  double max_time_difference_used = 0.0;  // largest |t_gt - t_est| among the pairs
};

// Pairs pose i with pose i. Throws std::invalid_argument if the sizes differ or are zero.
AssociatedTrajectories AssociateByIndex(const std::vector<SE3d>& gt, const std::vector<SE3d>& est);

// Pairs by nearest timestamp. Times must be non-decreasing and sizes must match their poses.
// Throws std::invalid_argument on bad input or when no pair is within the tolerance.
AssociatedTrajectories AssociateByTime(const std::vector<double>& times_gt,
                                       const std::vector<SE3d>& gt,
                                       const std::vector<double>& times_est,
                                       const std::vector<SE3d>& est,
                                       const AssociationOptions& options = {});

}  // namespace eval
}  // namespace plucker
