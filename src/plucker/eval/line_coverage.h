// Pixel-coverage precision, recall and F of 2D line segments against hand-annotated ones.
//   precision = share of the detected length lying within tau px of some ground-truth segment
//   recall    = share of the ground-truth length lying within tau px of some detected segment
//   F         = 2 P R / (P + R)
// Each segment is cut into ceil(length) pieces of equal length (one piece a pixel, at least one);
// a piece counts as covered when its midpoint is within tau of the other set. Pure geometry, no
// images. A segment is an Eigen::Vector4d (x1, y1, x2, y2) in pixels.
#pragma once

#include <utility>
#include <vector>

#include <Eigen/Core>

namespace plucker {
namespace eval {

using Segment2d = Eigen::Vector4d;  // x1 y1 x2 y2, pixels

// Covered and total lengths of both directions; add them up over images for an overall figure.
struct LineCoverage {
  double detected_length = 0.0;   // total length of the detections [px]
  double detected_covered = 0.0;  // of which within tau of the ground truth
  double gt_length = 0.0;         // total ground-truth length [px]
  double gt_covered = 0.0;        // of which within tau of a detection

  double Precision() const;  // 0 when nothing was detected
  double Recall() const;     // 0 when the ground truth is empty
  double F() const;          // 0 when P + R == 0
  LineCoverage& operator+=(const LineCoverage& other);
};

// Distance from point p to the segment s (to its endpoint for a degenerate segment).
double PointSegmentDistance(const Eigen::Vector2d& p, const Segment2d& s);

// Length of `segments` within tau of `reference` (first) and their total length (second).
// Unchecked: call ComputeLineCoverage for input that may be bad.
std::pair<double, double> CoveredLength(const std::vector<Segment2d>& segments,
                                        const std::vector<Segment2d>& reference, double tau);

// Both directions at once. Throws std::invalid_argument for tau < 0 and for a segment with a
// non-finite coordinate or one beyond 1e7 px.
LineCoverage ComputeLineCoverage(const std::vector<Segment2d>& detected,
                                 const std::vector<Segment2d>& ground_truth, double tau);

}  // namespace eval
}  // namespace plucker
