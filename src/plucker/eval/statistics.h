// Summary statistics of a list of non-negative errors.
#pragma once

#include <vector>

namespace plucker {
namespace eval {

struct ErrorStatistics {
  int count = 0;  // 0: every other field is 0 and meaningless
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;   // mean of the two middle values for an even count
  double std_dev = 0.0;  // population standard deviation
  double min = 0.0;
  double max = 0.0;
};

ErrorStatistics ComputeStatistics(const std::vector<double>& errors);

// The q-quantile (0 <= q <= 1) with linear interpolation between order statistics; 0 when empty.
double Percentile(std::vector<double> values, double q);

// Cumulative path length along a sequence of positions: out[0] = 0,
// out[i] = out[i-1] + |p_i - p_{i-1}|.
template <typename Vector>
std::vector<double> PathDistances(const std::vector<Vector>& positions) {
  std::vector<double> dist(positions.size(), 0.0);
  for (std::size_t i = 1; i < positions.size(); ++i) {
    dist[i] = dist[i - 1] + (positions[i] - positions[i - 1]).norm();
  }
  return dist;
}

}  // namespace eval
}  // namespace plucker
