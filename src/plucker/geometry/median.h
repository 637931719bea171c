// The median of a list as the estimators use it (window: keyframe parallax and landmark depth):
// the upper middle element v[n / 2] after a partial sort, no averaging for an even count (unlike
// eval::ComputeStatistics, whose median is the mean of the two middle values); 0 when empty.
// Header-only, Eigen-free: any layer may use it (window must not depend on eval).
#pragma once

#include <algorithm>
#include <vector>

namespace plucker {

inline double UpperMedian(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace plucker
