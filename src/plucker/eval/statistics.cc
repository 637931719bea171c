#include "plucker/eval/statistics.h"

#include <algorithm>
#include <cmath>

namespace plucker {
namespace eval {

ErrorStatistics ComputeStatistics(const std::vector<double>& errors) {
  ErrorStatistics s;
  if (errors.empty()) return s;
  s.count = static_cast<int>(errors.size());
  double sum = 0.0, sum_sq = 0.0;
  s.min = errors[0];
  s.max = errors[0];
  for (double e : errors) {
    sum += e;
    sum_sq += e * e;
    s.min = std::min(s.min, e);
    s.max = std::max(s.max, e);
  }
  const double n = static_cast<double>(errors.size());
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  s.std_dev = std::sqrt(std::max(0.0, sum_sq / n - s.mean * s.mean));
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t mid = sorted.size() / 2;
  s.median = sorted.size() % 2 == 1 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
  return s;
}

double Percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double pos = std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (pos - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

}  // namespace eval
}  // namespace plucker
