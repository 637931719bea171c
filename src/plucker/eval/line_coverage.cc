#include "plucker/eval/line_coverage.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

namespace plucker {
namespace eval {
namespace {

// Axis-aligned box of a segment grown by tau: a cheap reject before the exact distance.
struct Box {
  double x0, y0, x1, y1;
  bool Contains(const Eigen::Vector2d& p) const {
    return p.x() >= x0 && p.x() <= x1 && p.y() >= y0 && p.y() <= y1;
  }
};

Box GrownBox(const Segment2d& s, double tau) {
  return {std::min(s[0], s[2]) - tau, std::min(s[1], s[3]) - tau, std::max(s[0], s[2]) + tau,
          std::max(s[1], s[3]) + tau};
}

double Length(const Segment2d& s) { return std::hypot(s[2] - s[0], s[3] - s[1]); }

constexpr double kMaxCoordinate = 1e7;  // px: beyond it a segment is garbage, not an image

void CheckSegments(const std::vector<Segment2d>& segments, const char* which) {
  for (const Segment2d& s : segments) {
    if (!s.allFinite() || s.cwiseAbs().maxCoeff() > kMaxCoordinate) {
      throw std::invalid_argument(std::string("line coverage: a ") + which +
                                  " segment has a non-finite coordinate or one beyond 1e7 px");
    }
  }
}

}  // namespace

double LineCoverage::Precision() const {
  return detected_length > 0.0 ? detected_covered / detected_length : 0.0;
}

double LineCoverage::Recall() const { return gt_length > 0.0 ? gt_covered / gt_length : 0.0; }

double LineCoverage::F() const {
  const double p = Precision(), r = Recall();
  return p + r > 0.0 ? 2.0 * p * r / (p + r) : 0.0;
}

LineCoverage& LineCoverage::operator+=(const LineCoverage& other) {
  detected_length += other.detected_length;
  detected_covered += other.detected_covered;
  gt_length += other.gt_length;
  gt_covered += other.gt_covered;
  return *this;
}

double PointSegmentDistance(const Eigen::Vector2d& p, const Segment2d& s) {
  const Eigen::Vector2d a = s.head<2>(), d = s.tail<2>() - a;
  const double d2 = d.squaredNorm();
  const double t = d2 > 0.0 ? std::clamp((p - a).dot(d) / d2, 0.0, 1.0) : 0.0;
  return (p - (a + t * d)).norm();
}

std::pair<double, double> CoveredLength(const std::vector<Segment2d>& segments,
                                        const std::vector<Segment2d>& reference, double tau) {
  std::vector<Box> boxes;
  boxes.reserve(reference.size());
  for (const Segment2d& r : reference) boxes.push_back(GrownBox(r, tau));
  double covered = 0.0, total = 0.0;
  for (const Segment2d& s : segments) {
    const double length = Length(s);
    const int pieces = std::max(1, static_cast<int>(std::ceil(length)));
    const double piece_length = length / pieces;
    for (int i = 0; i < pieces; ++i) {
      const double t = (i + 0.5) / pieces;
      const Eigen::Vector2d p = s.head<2>() + t * (s.tail<2>() - s.head<2>());
      for (std::size_t k = 0; k < reference.size(); ++k) {
        if (boxes[k].Contains(p) && PointSegmentDistance(p, reference[k]) <= tau) {
          covered += piece_length;
          break;
        }
      }
    }
    total += length;
  }
  return {covered, total};
}

LineCoverage ComputeLineCoverage(const std::vector<Segment2d>& detected,
                                 const std::vector<Segment2d>& ground_truth, double tau) {
  if (!(tau >= 0.0)) throw std::invalid_argument("line coverage: tau must be >= 0");
  CheckSegments(detected, "detected");
  CheckSegments(ground_truth, "ground-truth");
  LineCoverage c;
  std::tie(c.detected_covered, c.detected_length) = CoveredLength(detected, ground_truth, tau);
  std::tie(c.gt_covered, c.gt_length) = CoveredLength(ground_truth, detected, tau);
  return c;
}

}  // namespace eval
}  // namespace plucker
