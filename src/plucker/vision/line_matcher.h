// Line segment description and two-view matching.
//
// Description (DescribeLines): the LBD binary descriptor of OpenCV's line_descriptor module
// (cv::line_descriptor::BinaryDescriptor::compute, 256 bits) on KeyLines built from our own
// segments (one octave, a unique class_id per segment). Before that every segment is
//   - clipped to the image (LBD's bands must stay mostly inside it) and dropped when shorter
//     than min_length_px;
//   - oriented by polarity: start and end are swapped when needed so that the brighter side is
//     on the left of start -> end (x right, y down). LBD is computed in the frame of the
//     segment direction, so the same edge must get the same direction in every image; the
//     orientation is also a matching gate (an edge does not change polarity between frames).
//
// Matching (MatchLines), for the segments a of one image and b of another:
//   1. geometric gates on every pair: direction change (oriented, in the image), length ratio,
//      distance between the midpoints, the predicted position (when given) and, when the
//      fundamental matrix F_b_a (x_b^T F x_a = 0) is known or estimated from points, overlap along
//      the epipolar lines: the epipolar lines of a's endpoints cut b's line in an interval whose
//      overlap with b, relative to the shorter of the two, must reach min_epipolar_overlap. Where b
//      is within min_epipolar_angle_deg of the epipolar lines the cut is undefined and this gate is
//      skipped (the pair is kept);
//   2. the Hamming distance of the surviving pairs: for every a the best and second-best b;
//      accepted when best <= max_hamming and best < ratio * second (when a second exists);
//   3. mutual nearest neighbour: a's best b must have a as its best a. Each segment is in at
//      most one match (also without the mutual test: then the lowest distance wins).
// No I/O, no printing, no timing.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "plucker/vision/line_detector.h"

namespace plucker {
namespace vision {

struct LineDescriberOptions {
  double min_length_px = 15.0;  // shorter segments (after clipping) are not described
  double border_px = 2.0;       // segments are clipped to [border, size - 1 - border]
  int band_width = 7;           // LBD band width [px] (OpenCV default 7)
  // LBD smooths and differentiates the whole image it is given: when the segments' bounding
  // boxes, widened by the bands' reach, cover less than the image, each is described on its
  // crop instead (the same descriptors; false: always the whole image).
  bool crop = true;
};

// Segments with their descriptors, row i of `descriptors` (CV_8UC1, 32 bytes) for segments[i].
struct LineFeatures {
  std::vector<Segment2d> segments;  // clipped and oriented (see above)
  std::vector<int> source_index;    // index of each in the input segment list
  cv::Mat descriptors;              // N x 32, CV_8UC1 (empty when N = 0)
  int size() const { return static_cast<int>(segments.size()); }
};

struct LineDescriptionStats {
  int input = 0;
  int rejected_short = 0;  // shorter than min_length_px after clipping (or outside the image)
  int flipped = 0;         // start and end swapped by polarity
  int described = 0;
};

// gray: CV_8UC1, non-empty (std::invalid_argument otherwise). Empty segment lists are fine.
LineFeatures DescribeLines(const cv::Mat& gray, const std::vector<Segment2d>& segments,
                           const LineDescriberOptions& options = {},
                           LineDescriptionStats* stats = nullptr);

// The two steps of DescribeLines, for callers that describe only some segments (line_tracker.h):
// PrepareLines clips and orients (descriptors left empty; the same segments and stats as
// DescribeLines), ComputeLineDescriptors gives the LBD rows of prepared segments (row i for
// prepared[i]; a segment's descriptor does not depend on the others in the list).
LineFeatures PrepareLines(const cv::Mat& gray, const std::vector<Segment2d>& segments,
                          const LineDescriberOptions& options = {},
                          LineDescriptionStats* stats = nullptr);
cv::Mat ComputeLineDescriptors(const cv::Mat& gray, const std::vector<Segment2d>& prepared,
                               const LineDescriberOptions& options = {});

struct LineMatcherOptions {
  int max_hamming = 50;         // of 256 bits
  double ratio = 0.8;           // best < ratio * second best (among gated candidates)
  bool mutual = true;           // mutual nearest neighbours only
  double max_angle_deg = 12.0;  // oriented direction change between the images
  double max_length_ratio = 3.0;
  double max_midpoint_distance_px = 150.0;  // <= 0: no limit
  double min_epipolar_overlap = 0.3;        // with F: overlap / shorter interval (see above)
  double min_epipolar_angle_deg = 4.0;      // below: the epipolar cut is skipped
  // With predicted positions of points of a in image b (e.g. optical flow of points sampled on
  // a, see line_tracker.h): the median distance of a's predicted points from b's infinite line
  // must not exceed this. Flow across an edge is well defined (only the component along it is
  // not), so this separates neighbouring parallel edges that descriptors confuse.
  // 0.5 px: a re-detected edge lies on the followed points to a fraction of a pixel, while a
  // neighbouring edge or an occluding contour that slides over the surface does not (KITTI clip,
  // README: precision of 3+ view tracks 88 % at 1 px, 96 % at 0.5 px).
  double max_prediction_distance_px = 0.5;
};

struct LineMatch {
  int a = -1, b = -1;   // indices into the LineFeatures a and b
  int distance = 0;     // Hamming distance of the descriptors
  double overlap = -1;  // epipolar overlap in [0, 1]; -1 when not measured
};

struct LineMatchStats {
  int a = 0, b = 0;         // segments in each image
  long pairs = 0;           // a x b
  long rejected_angle = 0;  // pair counts of the geometric gates, in this order
  long rejected_length = 0;
  long rejected_distance = 0;
  long rejected_epipolar = 0;
  long rejected_prediction = 0;
  long gated = 0;            // pairs that passed every geometric gate
  int no_candidate = 0;      // a with no gated b
  int rejected_hamming = 0;  // a whose best b is above max_hamming
  int rejected_ratio = 0;    // a whose best is not distinct enough from the second
  int rejected_mutual = 0;   // a whose best b prefers another a (or lost the uniqueness)
  int matches = 0;
};

struct LineMatchResult {
  std::vector<LineMatch> matches;  // sorted by a
  LineMatchStats stats;
};

// Predicted positions in image b of points of each segment of a (one list per segment of a; an
// empty list: no prediction, the gate is skipped for that segment).
using LinePredictions = std::vector<std::vector<Eigen::Vector2d>>;

// F_b_a: x_b^T F_b_a x_a = 0 for corresponding pixels (optional). predicted: see above
// (optional; its size must be a.size(), std::invalid_argument otherwise).
LineMatchResult MatchLines(const LineFeatures& a, const LineFeatures& b,
                           const LineMatcherOptions& options = {},
                           const std::optional<Eigen::Matrix3d>& F_b_a = std::nullopt,
                           const LinePredictions* predicted = nullptr);

// Step 1 of MatchLines alone (no descriptors needed): the pairs that pass every geometric gate,
// in the order (a, b); stats gets the counts up to `gated`.
struct GatedPair {
  int a = -1, b = -1;
  double overlap = -1;  // as LineMatch::overlap
};
std::vector<GatedPair> GateLinePairs(const LineFeatures& a, const LineFeatures& b,
                                     const LineMatcherOptions& options = {},
                                     const std::optional<Eigen::Matrix3d>& F_b_a = std::nullopt,
                                     const LinePredictions* predicted = nullptr,
                                     LineMatchStats* stats = nullptr);

// Overlap of segment b with the interval the epipolar lines of a's endpoints cut on b's line,
// relative to the shorter of the two, in [0, 1]; nullopt when b is within min_angle_deg of an
// epipolar line (the cut is undefined) or the input is degenerate.
std::optional<double> EpipolarOverlap(const Segment2d& a, const Segment2d& b,
                                      const Eigen::Matrix3d& F_b_a, double min_angle_deg);

// Hamming distance of two 32-byte descriptor rows.
int HammingDistance(const cv::Mat& descriptors_a, int row_a, const cv::Mat& descriptors_b,
                    int row_b);

}  // namespace vision
}  // namespace plucker
