// Line segment detection on grayscale images.
//
// Methods: OpenCV's raw detectors with their defaults (LSD, FastLineDetector, EdgeDrawing/EDLines)
// and the default `edlines-refined`:
//   0. EDLines without Gaussian smoothing (more, and sharper, edges: recall) and with a higher
//      anchor threshold (fewer weak anchors: precision, time),
//   1. a support test: the share of points along the segment where the Sobel gradient (within
//      one pixel across) is strong and perpendicular to the segment, i.e. the gradient-orientation
//      agreement behind LSD's validation; segments with too little support are dropped
//      (precision back),
//   2. optional refinement: a re-fit to the sub-pixel gradient maxima across the segment, a second
//      fit without the maxima far from the first (off by default: +0.001 F at 2 px on York
//      Urban, not worth its time; on Strecha fountain-P11 it lowers the line residuals of
//      `plucker sfm --refine-segments` but not the camera error, docs/results/sfm.md),
//   3. extension: each endpoint is pushed along the segment while the edge continues.
// Thresholds were tuned on the even-indexed York Urban images and checked on the odd ones
// (docs/results/lines.md, `plucker bench lines`).
// No file I/O, no printing, no timing: the caller times DetectLineSegments.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace plucker {
namespace vision {

using Segment2d = Eigen::Vector4d;  // x1 y1 x2 y2, pixels (origin top-left, pixel centres at
                                    // integer coordinates)

enum class LineMethod { kLsd, kFld, kEdlines, kEdlinesRefined };

// "lsd", "fld", "edlines", "edlines-refined"; std::nullopt for anything else.
std::optional<LineMethod> ParseLineMethod(const std::string& name);
std::string LineMethodName(LineMethod method);
std::string LineMethodNames();  // "lsd|fld|edlines|edlines-refined", for help texts

struct LineDetectorOptions {
  LineMethod method = LineMethod::kEdlinesRefined;
  double min_length = 0.0;  // segments shorter than this [px] are dropped at the end (0: keep)

  // EdgeDrawing of edlines-refined (the raw methods use OpenCV's defaults).
  double ed_sigma = 0.0;  // Gaussian smoothing; OpenCV's EdgeDrawing skips it below 1
  int ed_gradient_threshold = 20;
  int ed_anchor_threshold = 16;  // OpenCV default 0
  int ed_scan_interval = 1;
  // EDLines' own a-contrario (NFA) validation; off by default: the support test below validates
  // instead, at a quarter of EDLines' time less.
  bool ed_nfa_validation = false;

  // Support test (edlines-refined).
  bool support_filter = true;
  double support_angle_deg = 22.5;     // gradient within this of the segment normal counts
  double support_min_gradient = 30.0;  // and |Sobel gradient| (L1, 3x3) at least this
  double support_min_share = 0.85;     // share of supported points along the segment to keep it

  // Sub-pixel refinement (edlines-refined).
  bool refine = false;
  double refine_radius = 2.0;   // search across the segment up to this [px]
  double refine_trim_px = 0.5;  // maxima further from the first fit are left out of the second

  // Endpoint extension (edlines-refined).
  bool extend = true;
  double extend_min_gradient = 60.0;  // as support_min_gradient, for the continued edge
  int extend_max_gap = 1;             // unsupported steps allowed in a row [px]
  int extend_max = 40;                // at most this many px per endpoint
};

struct LineDetectionStats {
  int raw = 0;                   // segments from the underlying detector
  int rejected_support = 0;      // dropped by the support test
  int rejected_length = 0;       // dropped by min_length
  int refined = 0;               // re-fitted to gradient maxima
  double extended_length = 0.0;  // length added by endpoint extension [px]
  int kept = 0;                  // returned segments
};

struct LineDetection {
  std::vector<Segment2d> segments;
  LineDetectionStats stats;
};

// gray: CV_8UC1, non-empty (throws std::invalid_argument otherwise).
LineDetection DetectLineSegments(const cv::Mat& gray, const LineDetectorOptions& options = {});

}  // namespace vision
}  // namespace plucker
