// The one median of the code base, in its two variants (name the one you mean):
// - UpperMedian: the upper middle element v[n / 2] after a partial sort, no averaging for an even
//   count. What the estimators use (window keyframe parallax and landmark depth, two-view
//   parallax, the image-motion flag, SfM triangulation angles, frame-step checks): O(n), and the
//   value is one of the inputs.
// - MidpointMedian: the mean of the two middle values for an even count (the textbook median, as
//   eval::ComputeStatistics reports it). What the evaluation uses (camera-set errors).
// Both return 0 for an empty list. Header-only, Eigen-free: any layer may use it (window must not
// depend on eval).
#pragma once

#include <algorithm>
#include <vector>

namespace plucker {

inline double UpperMedian(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

inline double MidpointMedian(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace plucker
