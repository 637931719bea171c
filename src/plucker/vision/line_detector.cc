#include "plucker/vision/line_detector.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc.hpp>

namespace plucker {
namespace vision {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Sobel gradient of the image (CV_16S, 3x3), shared by Canny and the post-processing.
struct Gradient {
  cv::Mat dx, dy;

  bool Inside(double x, double y) const {
    return x >= 0.0 && y >= 0.0 && x <= dx.cols - 1.0 && y <= dx.rows - 1.0;
  }
  // Nearest pixel; the caller checks Inside.
  Eigen::Vector2d At(double x, double y) const {
    const int c = static_cast<int>(std::lround(x)), r = static_cast<int>(std::lround(y));
    return {dx.at<short>(r, c), dy.at<short>(r, c)};
  }
  // Bilinear; the caller checks Inside.
  Eigen::Vector2d Interpolated(double x, double y) const {
    const int c = std::min(static_cast<int>(x), dx.cols - 2);
    const int r = std::min(static_cast<int>(y), dx.rows - 2);
    const double u = x - c, v = y - r;
    auto blend = [&](const cv::Mat& m) {
      return (1 - v) * ((1 - u) * m.at<short>(r, c) + u * m.at<short>(r, c + 1)) +
             v * ((1 - u) * m.at<short>(r + 1, c) + u * m.at<short>(r + 1, c + 1));
    };
    return {blend(dx), blend(dy)};
  }
};

Gradient ComputeGradient(const cv::Mat& gray) {
  Gradient g;
  cv::Sobel(gray, g.dx, CV_16S, 1, 0, 3);
  cv::Sobel(gray, g.dy, CV_16S, 0, 1, 3);
  return g;
}

// A segment as a point, unit direction and length.
struct Frame {
  Eigen::Vector2d a, t, n;
  double length;
};

Frame MakeFrame(const Segment2d& s) {
  Frame f;
  f.a = s.head<2>();
  const Eigen::Vector2d d = s.tail<2>() - f.a;
  f.length = d.norm();
  f.t = f.length > 0.0 ? Eigen::Vector2d(d / f.length) : Eigen::Vector2d(1.0, 0.0);
  f.n = Eigen::Vector2d(-f.t.y(), f.t.x());
  return f;
}

double Length(const Segment2d& s) { return (s.tail<2>() - s.head<2>()).norm(); }

// Is there an edge across direction t at p (within one pixel across)?
class SupportTest {
 public:
  SupportTest(const Gradient& g, double angle_deg, double min_gradient)
      : g_(g),
        sin2_angle_(std::pow(std::sin(angle_deg * kPi / 180.0), 2)),
        min_gradient_(min_gradient) {}

  bool Supported(const Eigen::Vector2d& p, const Frame& f) const {
    for (int k : {0, -1, 1}) {
      const Eigen::Vector2d q = p + k * f.n;
      if (!g_.Inside(q.x(), q.y())) continue;
      const Eigen::Vector2d grad = g_.At(q.x(), q.y());
      // |grad . t| <= sin(angle) |grad|, squared.
      if (grad.lpNorm<1>() >= min_gradient_ &&
          grad.dot(f.t) * grad.dot(f.t) <= sin2_angle_ * grad.squaredNorm()) {
        return true;
      }
    }
    return false;
  }

  // Is at least `min_share` of the points (one a pixel) along s supported? Stops as soon as the
  // answer is known.
  bool HasShare(const Segment2d& s, double min_share) const {
    const Frame f = MakeFrame(s);
    const int n = std::max(1, static_cast<int>(f.length));
    const int needed = static_cast<int>(std::ceil(min_share * n));
    int supported = 0;
    for (int i = 0; i < n && supported < needed && supported + (n - i) >= needed; ++i) {
      supported += Supported(f.a + (i + 0.5) * f.length / n * f.t, f);
    }
    return supported >= needed;
  }

 private:
  const Gradient& g_;
  double sin2_angle_, min_gradient_;
};

// Re-fits s to the sub-pixel maxima of the gradient across it. False when too few maxima.
bool Refine(const Gradient& g, const LineDetectorOptions& o, Segment2d* s) {
  const Frame f = MakeFrame(*s);
  const int samples = static_cast<int>(f.length);
  const int steps = static_cast<int>(std::ceil(o.refine_radius));
  std::vector<Eigen::Vector3d> points;  // x, y, weight
  std::vector<double> profile(2 * steps + 1);
  for (int i = 0; i < samples; ++i) {
    const Eigen::Vector2d p = f.a + (i + 0.5) * f.length / samples * f.t;
    bool inside = true;
    for (int k = -steps; k <= steps && inside; ++k) {
      const Eigen::Vector2d q = p + k * f.n;
      inside = g.Inside(q.x(), q.y());
      if (inside) profile[k + steps] = std::abs(g.Interpolated(q.x(), q.y()).dot(f.n));
    }
    if (!inside) continue;
    const int best = static_cast<int>(std::max_element(profile.begin() + 1, profile.end() - 1) -
                                      profile.begin());
    const double l = profile[best - 1], c = profile[best], r = profile[best + 1];
    if (c < o.support_min_gradient || c < l || c < r) continue;
    const double denominator = l - 2.0 * c + r;
    const double offset = denominator < 0.0 ? 0.5 * (l - r) / denominator : 0.0;
    const Eigen::Vector2d q = p + (best - steps + offset) * f.n;
    points.emplace_back(q.x(), q.y(), c);
  }
  if (points.size() < 4 || points.size() < 0.5 * samples) return false;
  // Weighted total least squares line through the maxima, fitted twice: the second time without
  // the maxima further than refine_trim_px from the first line (a neighbouring edge within the
  // search radius, a corner at an end).
  Eigen::Vector2d mean, t;
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      const Eigen::Vector2d normal(-t.y(), t.x());
      points.erase(std::remove_if(points.begin(), points.end(),
                                  [&](const Eigen::Vector3d& p) {
                                    return std::abs((p.head<2>() - mean).dot(normal)) >
                                           o.refine_trim_px;
                                  }),
                   points.end());
      if (points.size() < 4 || points.size() < 0.5 * samples) return false;
    }
    double w = 0.0;
    mean.setZero();
    for (const Eigen::Vector3d& p : points) mean += p.z() * p.head<2>(), w += p.z();
    mean /= w;
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (const Eigen::Vector3d& p : points) {
      const Eigen::Vector2d d = p.head<2>() - mean;
      scatter += p.z() * d * d.transpose();
    }
    t = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(scatter).eigenvectors().col(1);
  }
  if (t.dot(f.t) < 0.0) t = -t;
  if (t.dot(f.t) < std::cos(5.0 * kPi / 180.0)) return false;  // not the same edge
  const Eigen::Vector2d a = mean + (s->head<2>() - mean).dot(t) * t;
  const Eigen::Vector2d b = mean + (s->tail<2>() - mean).dot(t) * t;
  if ((a - s->head<2>()).norm() > o.refine_radius || (b - s->tail<2>()).norm() > o.refine_radius) {
    return false;
  }
  *s << a, b;
  return true;
}

// Moves one endpoint outwards (direction `out`) while the edge continues. Returns the length added.
double ExtendEnd(const SupportTest& support, const Gradient& g, const LineDetectorOptions& o,
                 const Frame& f, const Eigen::Vector2d& out, Eigen::Vector2d* end) {
  int last = 0, gap = 0;
  for (int step = 1; step <= o.extend_max; ++step) {
    const Eigen::Vector2d p = *end + step * out;
    if (!g.Inside(p.x(), p.y())) break;
    if (support.Supported(p, f)) {
      last = step;
      gap = 0;
    } else if (++gap > o.extend_max_gap) {
      break;
    }
  }
  *end += last * out;
  return last;
}

double Extend(const SupportTest& support, const Gradient& g, const LineDetectorOptions& o,
              Segment2d* s) {
  const Frame f = MakeFrame(*s);
  Eigen::Vector2d a = s->head<2>(), b = s->tail<2>();
  const double added = ExtendEnd(support, g, o, f, -f.t, &a) + ExtendEnd(support, g, o, f, f.t, &b);
  *s << a, b;
  return added;
}

std::vector<Segment2d> ToSegments(const std::vector<cv::Vec4f>& lines) {
  std::vector<Segment2d> out;
  out.reserve(lines.size());
  for (const cv::Vec4f& l : lines) out.emplace_back(l[0], l[1], l[2], l[3]);
  return out;
}

std::vector<Segment2d> RawOpenCv(const cv::Mat& gray, const LineDetectorOptions& o) {
  std::vector<cv::Vec4f> lines;
  switch (o.method) {
    case LineMethod::kLsd:
      cv::createLineSegmentDetector(cv::LSD_REFINE_STD)->detect(gray, lines);
      break;
    case LineMethod::kEdlines: {
      cv::Ptr<cv::ximgproc::EdgeDrawing> ed = cv::ximgproc::createEdgeDrawing();  // defaults
      ed->detectEdges(gray);
      ed->detectLines(lines);
      break;
    }
    default:
      cv::ximgproc::createFastLineDetector()->detect(gray, lines);  // defaults
  }
  return ToSegments(lines);
}

cv::Ptr<cv::ximgproc::EdgeDrawing> MakeEdgeDrawing(const LineDetectorOptions& o) {
  cv::Ptr<cv::ximgproc::EdgeDrawing> ed = cv::ximgproc::createEdgeDrawing();
  ed->params.Sigma = static_cast<float>(o.ed_sigma);
  ed->params.GradientThresholdValue = o.ed_gradient_threshold;
  ed->params.AnchorThresholdValue = o.ed_anchor_threshold;
  ed->params.ScanInterval = o.ed_scan_interval;
  ed->params.NFAValidation = o.ed_nfa_validation;
  return ed;
}

// edlines-refined: EDLines without smoothing (more recall), then the support test, refinement
// and extension.
std::vector<Segment2d> EdlinesRefined(const cv::Mat& gray, const LineDetectorOptions& o,
                                      LineDetectionStats* stats) {
  std::vector<cv::Vec4f> lines;
  cv::Ptr<cv::ximgproc::EdgeDrawing> ed = MakeEdgeDrawing(o);
  ed->detectEdges(gray);
  ed->detectLines(lines);
  std::vector<Segment2d> segments = ToSegments(lines);
  stats->raw = static_cast<int>(segments.size());
  const Gradient g = ComputeGradient(gray);
  const SupportTest support(g, o.support_angle_deg, o.support_min_gradient);
  const SupportTest continues(g, o.support_angle_deg, o.extend_min_gradient);
  std::vector<Segment2d> kept;
  kept.reserve(segments.size());
  for (Segment2d& s : segments) {
    if (o.support_filter && !support.HasShare(s, o.support_min_share)) {
      ++stats->rejected_support;
      continue;
    }
    if (o.refine && Refine(g, o, &s)) ++stats->refined;
    if (o.extend) stats->extended_length += Extend(continues, g, o, &s);
    kept.push_back(s);
  }
  return kept;
}

}  // namespace

std::optional<LineMethod> ParseLineMethod(const std::string& name) {
  for (LineMethod m :
       {LineMethod::kLsd, LineMethod::kFld, LineMethod::kEdlines, LineMethod::kEdlinesRefined}) {
    if (name == LineMethodName(m)) return m;
  }
  return std::nullopt;
}

std::string LineMethodName(LineMethod method) {
  switch (method) {
    case LineMethod::kLsd:
      return "lsd";
    case LineMethod::kFld:
      return "fld";
    case LineMethod::kEdlines:
      return "edlines";
    case LineMethod::kEdlinesRefined:
      return "edlines-refined";
  }
  return "?";
}

std::string LineMethodNames() { return "lsd|fld|edlines|edlines-refined"; }

LineDetection DetectLineSegments(const cv::Mat& gray, const LineDetectorOptions& options) {
  if (gray.empty() || gray.type() != CV_8UC1) {
    throw std::invalid_argument("DetectLineSegments: needs a non-empty 8-bit grayscale image");
  }
  LineDetection result;
  std::vector<Segment2d> segments;
  if (options.method == LineMethod::kEdlinesRefined) {
    segments = EdlinesRefined(gray, options, &result.stats);
  } else {
    segments = RawOpenCv(gray, options);
    result.stats.raw = static_cast<int>(segments.size());
  }
  for (const Segment2d& s : segments) {
    if (Length(s) < options.min_length) {
      ++result.stats.rejected_length;
    } else {
      result.segments.push_back(s);
    }
  }
  result.stats.kept = static_cast<int>(result.segments.size());
  return result;
}

}  // namespace vision
}  // namespace plucker
