#include "plucker/vision/line_matcher.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>

#include <opencv2/line_descriptor.hpp>

namespace plucker {
namespace vision {
namespace {

constexpr int kDescriptorBytes = 32;
constexpr int kLbdBands = 9;           // the bands of OpenCV's LBD (fixed in its implementation)
constexpr int kLbdFilterMarginPx = 8;  // its 5x5 Gaussian and 3x3 Sobel, with room to spare

// Liang-Barsky clip of s to [lo, hi] in both coordinates; false when nothing is left.
bool Clip(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, Segment2d* s) {
  const Eigen::Vector2d p((*s)[0], (*s)[1]), d = Eigen::Vector2d((*s)[2], (*s)[3]) - p;
  double t0 = 0.0, t1 = 1.0;
  for (int k = 0; k < 2; ++k) {
    for (const auto& [q, r] :
         {std::make_pair(-d[k], p[k] - lo[k]), std::make_pair(d[k], hi[k] - p[k])}) {
      if (q == 0.0) {
        if (r < 0.0) return false;
        continue;
      }
      const double t = r / q;
      if (q < 0.0) {
        t0 = std::max(t0, t);
      } else {
        t1 = std::min(t1, t);
      }
    }
  }
  if (!(t0 < t1)) return false;
  const Eigen::Vector2d a = p + t0 * d, b = p + t1 * d;
  *s = Segment2d(a.x(), a.y(), b.x(), b.y());
  return true;
}

double Bilinear(const cv::Mat& gray, double x, double y) {
  x = std::clamp(x, 0.0, gray.cols - 1.0);
  y = std::clamp(y, 0.0, gray.rows - 1.0);
  const int x0 = std::min(static_cast<int>(x), gray.cols - 2 < 0 ? 0 : gray.cols - 2);
  const int y0 = std::min(static_cast<int>(y), gray.rows - 2 < 0 ? 0 : gray.rows - 2);
  const int x1 = std::min(x0 + 1, gray.cols - 1), y1 = std::min(y0 + 1, gray.rows - 1);
  const double fx = x - x0, fy = y - y0;
  const auto at = [&](int r, int c) { return static_cast<double>(gray.at<uchar>(r, c)); };
  return (1 - fy) * ((1 - fx) * at(y0, x0) + fx * at(y0, x1)) +
         fy * ((1 - fx) * at(y1, x0) + fx * at(y1, x1));
}

// Sum of the intensity difference across the segment: side n = (dy, -dx) minus side -n.
double Polarity(const cv::Mat& gray, const Segment2d& s) {
  const Eigen::Vector2d p(s[0], s[1]), d = Eigen::Vector2d(s[2], s[3]) - p;
  const Eigen::Vector2d n = Eigen::Vector2d(d.y(), -d.x()).normalized() * 2.0;
  const int samples = std::clamp(static_cast<int>(d.norm() / 3.0), 3, 40);
  double sum = 0.0;
  for (int i = 0; i < samples; ++i) {
    const Eigen::Vector2d q = p + (i + 0.5) / samples * d;
    sum +=
        Bilinear(gray, q.x() + n.x(), q.y() + n.y()) - Bilinear(gray, q.x() - n.x(), q.y() - n.y());
  }
  return sum;
}

cv::line_descriptor::KeyLine MakeKeyLine(const Segment2d& s, int id, const cv::Size& image) {
  cv::line_descriptor::KeyLine kl;
  const float sx = static_cast<float>(s[0]), sy = static_cast<float>(s[1]);
  const float ex = static_cast<float>(s[2]), ey = static_cast<float>(s[3]);
  kl.startPointX = kl.sPointInOctaveX = sx;
  kl.startPointY = kl.sPointInOctaveY = sy;
  kl.endPointX = kl.ePointInOctaveX = ex;
  kl.endPointY = kl.ePointInOctaveY = ey;
  kl.lineLength = std::hypot(ex - sx, ey - sy);
  kl.numOfPixels = static_cast<int>(std::ceil(kl.lineLength));
  kl.angle = std::atan2(ey - sy, ex - sx);
  kl.pt = cv::Point2f(0.5f * (sx + ex), 0.5f * (sy + ey));
  kl.size = std::abs(ex - sx) * std::abs(ey - sy);
  kl.response = kl.lineLength / static_cast<float>(std::max(image.width, image.height));
  kl.octave = 0;
  kl.class_id = id;
  return kl;
}

Eigen::Vector2d Start(const Segment2d& s) { return Eigen::Vector2d(s[0], s[1]); }
Eigen::Vector2d End(const Segment2d& s) { return Eigen::Vector2d(s[2], s[3]); }

enum class Gate { kPass, kAngle, kLength, kDistance, kPrediction, kEpipolar };

// Whether the median distance of the points from the infinite line of b is at most t, i.e.
// at least n / 2 + 1 of the n points are within t (the upper median; no sorting, no allocation).
bool MedianLineDistanceWithin(const std::vector<Eigen::Vector2d>& points, const Segment2d& b,
                              double t) {
  const Eigen::Vector2d d = (End(b) - Start(b)).normalized();
  const Eigen::Vector2d n(-d.y(), d.x());
  const double c = n.dot(Start(b));
  const int needed = static_cast<int>(points.size()) / 2 + 1;
  int within = 0, left = static_cast<int>(points.size());
  for (const Eigen::Vector2d& p : points) {
    within += std::abs(n.dot(p) - c) <= t;
    --left;
    if (within >= needed) return true;
    if (within + left < needed) return false;
  }
  return false;
}

// Per-segment quantities the gates reuse for every pair.
struct SegmentGeometry {
  Eigen::Vector2d start, end, delta, mid;
  double length = 0.0;
};

SegmentGeometry Geometry(const Segment2d& s) {
  SegmentGeometry g;
  g.start = Start(s);
  g.end = End(s);
  g.delta = g.end - g.start;
  g.mid = 0.5 * (g.start + g.end);
  g.length = g.delta.norm();
  return g;
}

// The epipolar lines in b of a segment's endpoints (F_b_a x_a for each).
struct EpipolarLines {
  Eigen::Vector3d start, end;
};

std::optional<double> OverlapOfEpipolarLines(const EpipolarLines& l, const SegmentGeometry& b,
                                             double min_sin) {
  if (!(b.length > 0) || !l.start.allFinite() || !l.end.allFinite()) return std::nullopt;
  const Eigen::Vector3d bs = b.start.homogeneous();
  double t[2];
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector3d& e = k == 0 ? l.start : l.end;
    const double along = e.head<2>().dot(b.delta);  // |l_xy| |delta| sin(angle(b, l))
    if (!(std::abs(along) > min_sin * e.head<2>().norm() * b.length)) return std::nullopt;
    t[k] = -e.dot(bs) / along;
  }
  const double lo = std::min(t[0], t[1]), hi = std::max(t[0], t[1]);
  const double shorter = std::min(hi - lo, 1.0);
  if (!(shorter > 1e-6) || !std::isfinite(hi)) return std::nullopt;
  const double overlap = std::max(0.0, std::min(hi, 1.0) - std::max(lo, 0.0));
  return std::min(1.0, overlap / shorter);
}

struct GateConstants {
  double tan_max_angle = 0.0;      // tan(max_angle_deg) (max_angle_deg < 90)
  bool any_angle = false;          // max_angle_deg >= 180: no angle gate
  bool up_to_right_angle = false;  // 90 <= max_angle_deg < 180: cos gate
  double cos_max_angle = 0.0;
  double min_sin_epipolar = 0.0;
};

GateConstants Constants(const LineMatcherOptions& o) {
  GateConstants c;
  const double a = o.max_angle_deg * M_PI / 180.0;
  c.any_angle = !(a < M_PI);
  c.up_to_right_angle = !(a < 0.5 * M_PI);
  c.tan_max_angle = std::tan(a);
  c.cos_max_angle = std::cos(a);
  c.min_sin_epipolar = std::sin(o.min_epipolar_angle_deg * M_PI / 180.0);
  return c;
}

// The oriented angle between da and db is at most the maximum (atan2(|cross|, dot) <= max,
// without the atan2).
bool AngleWithin(const SegmentGeometry& a, const SegmentGeometry& b, const GateConstants& c) {
  if (c.any_angle) return true;
  const double cross = std::abs(a.delta.x() * b.delta.y() - a.delta.y() * b.delta.x());
  const double dot = a.delta.dot(b.delta);
  if (c.up_to_right_angle) return dot >= c.cos_max_angle * a.length * b.length;
  return dot > 0.0 && cross <= c.tan_max_angle * dot;
}

Gate GatePair(const SegmentGeometry& a, const SegmentGeometry& b, const LineMatcherOptions& o,
              const GateConstants& c, const EpipolarLines* epipolar, const Segment2d& b_segment,
              const std::vector<Eigen::Vector2d>* predicted, double* overlap) {
  if (!AngleWithin(a, b, c)) return Gate::kAngle;
  if (!(std::max(a.length, b.length) <= o.max_length_ratio * std::min(a.length, b.length)))
    return Gate::kLength;
  if (o.max_midpoint_distance_px > 0.0 && !((a.mid - b.mid).norm() <= o.max_midpoint_distance_px))
    return Gate::kDistance;
  if (predicted && !predicted->empty() &&
      !MedianLineDistanceWithin(*predicted, b_segment, o.max_prediction_distance_px)) {
    return Gate::kPrediction;
  }
  *overlap = -1.0;
  if (epipolar) {
    const auto ov = OverlapOfEpipolarLines(*epipolar, b, c.min_sin_epipolar);
    if (ov) {
      *overlap = *ov;
      if (!(*ov >= o.min_epipolar_overlap)) return Gate::kEpipolar;
    }
  }
  return Gate::kPass;
}

}  // namespace

LineFeatures PrepareLines(const cv::Mat& gray, const std::vector<Segment2d>& segments,
                          const LineDescriberOptions& options, LineDescriptionStats* stats) {
  if (gray.empty() || gray.type() != CV_8UC1) {
    throw std::invalid_argument("DescribeLines: the image must be non-empty 8-bit grayscale");
  }
  if (!(options.min_length_px > 0) || !(options.border_px >= 0) || options.band_width < 1) {
    throw std::invalid_argument("DescribeLines: invalid options");
  }
  LineDescriptionStats local;
  LineDescriptionStats& st = stats ? *stats : local;
  st = LineDescriptionStats{};
  st.input = static_cast<int>(segments.size());
  LineFeatures out;
  const Eigen::Vector2d lo(options.border_px, options.border_px);
  const Eigen::Vector2d hi(gray.cols - 1 - options.border_px, gray.rows - 1 - options.border_px);
  for (std::size_t i = 0; i < segments.size(); ++i) {
    Segment2d s = segments[i];
    if (!s.allFinite() || !(hi.x() > lo.x() && hi.y() > lo.y()) || !Clip(lo, hi, &s) ||
        !((End(s) - Start(s)).norm() >= options.min_length_px)) {
      ++st.rejected_short;
      continue;
    }
    if (Polarity(gray, s) < 0.0) {
      s = Segment2d(s[2], s[3], s[0], s[1]);
      ++st.flipped;
    }
    out.segments.push_back(s);
    out.source_index.push_back(static_cast<int>(i));
  }
  st.described = out.size();
  return out;
}

cv::Mat ComputeLineDescriptors(const cv::Mat& gray, const std::vector<Segment2d>& prepared,
                               const LineDescriberOptions& options) {
  if (gray.empty() || gray.type() != CV_8UC1 || options.band_width < 1) {
    throw std::invalid_argument("ComputeLineDescriptors: invalid image or options");
  }
  cv::Mat descriptors;
  if (prepared.empty()) return descriptors;
  cv::line_descriptor::BinaryDescriptor::Params params;
  params.numOfOctave_ = 1;
  params.widthOfBand_ = options.band_width;
  const cv::Ptr<cv::line_descriptor::BinaryDescriptor> lbd =
      cv::line_descriptor::BinaryDescriptor::createBinaryDescriptor(params);
  // LBD reads bands of kLbdBands * band_width px across each segment (options.crop).
  const int margin = (kLbdBands * options.band_width + 1) / 2 + kLbdFilterMarginPx;
  const cv::Rect whole(0, 0, gray.cols, gray.rows);
  std::vector<cv::Rect> crops;
  double crop_area = 0.0;
  for (const Segment2d& s : prepared) {
    const int x0 = static_cast<int>(std::floor(std::min(s[0], s[2]))) - margin;
    const int y0 = static_cast<int>(std::floor(std::min(s[1], s[3]))) - margin;
    const int x1 = static_cast<int>(std::ceil(std::max(s[0], s[2]))) + margin + 1;
    const int y1 = static_cast<int>(std::ceil(std::max(s[1], s[3]))) + margin + 1;
    crops.push_back(cv::Rect(x0, y0, x1 - x0, y1 - y0) & whole);
    crop_area += crops.back().area();
  }
  if (!options.crop || crop_area >= whole.area()) {
    std::vector<cv::line_descriptor::KeyLine> keylines;
    for (std::size_t i = 0; i < prepared.size(); ++i) {
      keylines.push_back(MakeKeyLine(prepared[i], static_cast<int>(i), gray.size()));
    }
    lbd->compute(gray, keylines, descriptors);
  } else {
    descriptors.create(static_cast<int>(prepared.size()), kDescriptorBytes, CV_8UC1);
    for (std::size_t i = 0; i < prepared.size(); ++i) {
      const cv::Rect& r = crops[i];
      const Segment2d s = prepared[i] - Eigen::Vector4d(r.x, r.y, r.x, r.y);
      std::vector<cv::line_descriptor::KeyLine> keylines = {MakeKeyLine(s, 0, gray.size())};
      cv::Mat row;
      lbd->compute(gray(r), keylines, row);
      if (row.rows != 1 || row.cols != kDescriptorBytes || row.type() != CV_8UC1) {
        throw std::runtime_error("DescribeLines: unexpected LBD descriptor layout");
      }
      row.copyTo(descriptors.row(static_cast<int>(i)));
    }
  }
  if (descriptors.rows != static_cast<int>(prepared.size()) ||
      descriptors.cols != kDescriptorBytes || descriptors.type() != CV_8UC1) {
    throw std::runtime_error("DescribeLines: unexpected LBD descriptor layout");
  }
  return descriptors;
}

LineFeatures DescribeLines(const cv::Mat& gray, const std::vector<Segment2d>& segments,
                           const LineDescriberOptions& options, LineDescriptionStats* stats) {
  LineFeatures out = PrepareLines(gray, segments, options, stats);
  out.descriptors = ComputeLineDescriptors(gray, out.segments, options);
  return out;
}

int HammingDistance(const cv::Mat& da, int ra, const cv::Mat& db, int rb) {
  const uchar* pa = da.ptr<uchar>(ra);
  const uchar* pb = db.ptr<uchar>(rb);
  int distance = 0;
  for (int k = 0; k < kDescriptorBytes; k += 8) {
    std::uint64_t x, y;
    std::memcpy(&x, pa + k, 8);
    std::memcpy(&y, pb + k, 8);
    distance += __builtin_popcountll(x ^ y);
  }
  return distance;
}

std::optional<double> EpipolarOverlap(const Segment2d& a, const Segment2d& b,
                                      const Eigen::Matrix3d& F_b_a, double min_angle_deg) {
  if (!F_b_a.allFinite()) return std::nullopt;
  const EpipolarLines l{F_b_a * Start(a).homogeneous(), F_b_a * End(a).homogeneous()};
  return OverlapOfEpipolarLines(l, Geometry(b), std::sin(min_angle_deg * M_PI / 180.0));
}

std::vector<GatedPair> GateLinePairs(const LineFeatures& a, const LineFeatures& b,
                                     const LineMatcherOptions& o,
                                     const std::optional<Eigen::Matrix3d>& F_b_a,
                                     const LinePredictions* predicted, LineMatchStats* stats) {
  if (predicted && static_cast<int>(predicted->size()) != a.size()) {
    throw std::invalid_argument("MatchLines: one prediction list per segment of a expected");
  }
  LineMatchStats local;
  LineMatchStats& st = stats ? *stats : local;
  st = LineMatchStats{};
  st.a = a.size();
  st.b = b.size();
  st.pairs = static_cast<long>(st.a) * st.b;
  std::vector<GatedPair> out;
  if (st.a == 0 || st.b == 0) return out;
  const GateConstants constants = Constants(o);
  std::vector<SegmentGeometry> geometry_b(st.b);
  for (int j = 0; j < st.b; ++j) geometry_b[j] = Geometry(b.segments[j]);
  const bool use_f = F_b_a.has_value() && F_b_a->allFinite();
  for (int i = 0; i < st.a; ++i) {
    const SegmentGeometry geometry_a = Geometry(a.segments[i]);
    EpipolarLines epipolar;
    if (use_f) {
      epipolar.start = *F_b_a * geometry_a.start.homogeneous();
      epipolar.end = *F_b_a * geometry_a.end.homogeneous();
    }
    for (int j = 0; j < st.b; ++j) {
      double overlap = -1.0;
      switch (GatePair(geometry_a, geometry_b[j], o, constants, use_f ? &epipolar : nullptr,
                       b.segments[j], predicted ? &(*predicted)[i] : nullptr, &overlap)) {
        case Gate::kAngle:
          ++st.rejected_angle;
          continue;
        case Gate::kLength:
          ++st.rejected_length;
          continue;
        case Gate::kDistance:
          ++st.rejected_distance;
          continue;
        case Gate::kPrediction:
          ++st.rejected_prediction;
          continue;
        case Gate::kEpipolar:
          ++st.rejected_epipolar;
          continue;
        case Gate::kPass:
          break;
      }
      ++st.gated;
      out.push_back({i, j, overlap});
    }
  }
  return out;
}

LineMatchResult MatchLines(const LineFeatures& a, const LineFeatures& b,
                           const LineMatcherOptions& o, const std::optional<Eigen::Matrix3d>& F_b_a,
                           const LinePredictions* predicted) {
  LineMatchResult result;
  LineMatchStats& st = result.stats;
  const std::vector<GatedPair> gated = GateLinePairs(a, b, o, F_b_a, predicted, &st);
  if (st.a == 0 || st.b == 0) {
    st.no_candidate = st.a;
    return result;
  }
  // Distances of the gated pairs (-1: gated out) and their epipolar overlaps.
  std::vector<int> dist(static_cast<std::size_t>(st.pairs), -1);
  std::vector<double> overlaps(dist.size(), -1.0);
  for (const GatedPair& g : gated) {
    const std::size_t k = static_cast<std::size_t>(g.a) * st.b + g.b;
    dist[k] = HammingDistance(a.descriptors, g.a, b.descriptors, g.b);
    overlaps[k] = g.overlap;
  }
  // Best a for every b (for the mutual test and for uniqueness).
  std::vector<int> best_a(st.b, -1), best_a_dist(st.b, std::numeric_limits<int>::max());
  for (int i = 0; i < st.a; ++i) {
    for (int j = 0; j < st.b; ++j) {
      const int d = dist[static_cast<std::size_t>(i) * st.b + j];
      if (d >= 0 && d < best_a_dist[j]) {
        best_a_dist[j] = d;
        best_a[j] = i;
      }
    }
  }
  std::vector<LineMatch> candidates;
  for (int i = 0; i < st.a; ++i) {
    int best = -1, d1 = std::numeric_limits<int>::max(), d2 = d1;
    for (int j = 0; j < st.b; ++j) {
      const int d = dist[static_cast<std::size_t>(i) * st.b + j];
      if (d < 0) continue;
      if (d < d1) {
        d2 = d1;
        d1 = d;
        best = j;
      } else if (d < d2) {
        d2 = d;
      }
    }
    if (best < 0) {
      ++st.no_candidate;
      continue;
    }
    if (d1 > o.max_hamming) {
      ++st.rejected_hamming;
      continue;
    }
    if (d2 != std::numeric_limits<int>::max() && !(d1 < o.ratio * d2)) {
      ++st.rejected_ratio;
      continue;
    }
    if (o.mutual && best_a[best] != i) {
      ++st.rejected_mutual;
      continue;
    }
    candidates.push_back({i, best, d1, overlaps[static_cast<std::size_t>(i) * st.b + best]});
  }
  // Uniqueness without the mutual test: the lowest distance keeps b (ties: the lower a).
  std::vector<int> owner(st.b, -1);
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    int& w = owner[candidates[k].b];
    if (w < 0 || candidates[k].distance < candidates[w].distance) w = static_cast<int>(k);
  }
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    if (owner[candidates[k].b] == static_cast<int>(k)) {
      result.matches.push_back(candidates[k]);
    } else {
      ++st.rejected_mutual;
    }
  }
  st.matches = static_cast<int>(result.matches.size());
  return result;
}

}  // namespace vision
}  // namespace plucker
