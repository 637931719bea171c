#include "plucker/eval/kitti_metric.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "plucker/eval/alignment.h"
#include "plucker/eval/statistics.h"

namespace plucker {
namespace eval {
namespace {

// The devkit's lastFrameFromSegmentLength: the first frame strictly farther than `len`.
int LastFrameFromSegmentLength(const std::vector<double>& dist, int first, double len) {
  for (int i = first; i < static_cast<int>(dist.size()); ++i) {
    if (dist[i] > dist[first] + len) return i;
  }
  return -1;
}

constexpr double kRadToDeg = 180.0 / M_PI;

}  // namespace

double DevkitRotationAngle(const Eigen::Matrix3d& R) {
  const double d = 0.5 * (R(0, 0) + R(1, 1) + R(2, 2) - 1.0);
  return std::acos(std::max(std::min(d, 1.0), -1.0));
}

KittiResult ComputeKittiMetric(const std::vector<SE3d>& gt, const std::vector<SE3d>& est,
                               const KittiOptions& options) {
  if (gt.size() != est.size()) {
    throw std::invalid_argument("the KITTI metric compares frame by frame: the ground truth has " +
                                std::to_string(gt.size()) + " poses, the estimate " +
                                std::to_string(est.size()));
  }
  if (gt.empty()) throw std::invalid_argument("no poses");
  if (options.step_size < 1) throw std::invalid_argument("the step size must be >= 1");
  for (double len : options.lengths) {
    if (!(len > 0.0) || !std::isfinite(len)) {
      throw std::invalid_argument("segment lengths must be positive");
    }
  }
  KittiResult r;
  r.pose_count = static_cast<int>(gt.size());
  r.distance = PathDistances(Positions(gt));
  r.path_length = r.distance.back();

  for (int first = 0; first < r.pose_count; first += options.step_size) {
    for (double len : options.lengths) {
      const int last = LastFrameFromSegmentLength(r.distance, first, len);
      if (last < 0) continue;
      const Eigen::Matrix4d G = gt[first].Matrix().inverse() * gt[last].Matrix();
      const Eigen::Matrix4d P = est[first].Matrix().inverse() * est[last].Matrix();
      const Eigen::Matrix4d E = P.inverse() * G;
      KittiSegment s;
      s.first = first;
      s.last = last;
      s.length = len;
      s.translation_error = E.topRightCorner<3, 1>().norm() / len;
      s.rotation_error = DevkitRotationAngle(E.topLeftCorner<3, 3>()) / len;
      s.speed = len / ((last - first + 1) / options.frame_rate_hz);
      r.segments.push_back(s);
    }
  }
  r.segment_count = static_cast<int>(r.segments.size());
  if (r.segment_count > 0) {
    double t_sum = 0.0, r_sum = 0.0;
    for (const KittiSegment& s : r.segments) {
      t_sum += s.translation_error;
      r_sum += s.rotation_error;
    }
    r.translation_error_percent = 100.0 * t_sum / r.segment_count;
    r.rotation_error_deg_per_m = kRadToDeg * r_sum / r.segment_count;
    r.rotation_error_deg_per_100m = 100.0 * *r.rotation_error_deg_per_m;
  }
  for (double len : options.lengths) {
    KittiLengthResult l;
    l.length = len;
    double t_sum = 0.0, r_sum = 0.0;
    for (const KittiSegment& s : r.segments) {
      if (s.length != len) continue;
      ++l.segment_count;
      t_sum += s.translation_error;
      r_sum += s.rotation_error;
    }
    if (l.segment_count > 0) {
      l.translation_error_percent = 100.0 * t_sum / l.segment_count;
      l.rotation_error_deg_per_100m = 100.0 * kRadToDeg * r_sum / l.segment_count;
    }
    r.per_length.push_back(l);
  }
  return r;
}

}  // namespace eval
}  // namespace plucker
