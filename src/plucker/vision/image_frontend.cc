#include "plucker/vision/image_frontend.h"

#include <algorithm>
#include <optional>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace plucker {
namespace vision {
namespace {

constexpr int kMinEpipolarTracks = 15;  // as FundamentalFromPointTracks' min_points

}  // namespace

ImageFrontend::ImageFrontend(const PinholeIntrinsics& K, const ImageFrontendOptions& options)
    : K_(K), options_(options), point_tracker_(options.points, K), line_tracker_(options.lines) {
  if (options.max_segments < 0)
    throw std::invalid_argument("ImageFrontend: max_segments must be >= 0");
  if (!(options.detection_scale > 0.0 && options.detection_scale <= 1.0))
    throw std::invalid_argument("ImageFrontend: detection_scale must be in (0, 1]");
}

ImageFrontendFrame ImageFrontend::Process(const cv::Mat& gray, const FrontendObserver& observer) {
  auto announce = [&](FrontendStage s) {
    if (observer) observer(s);
  };
  ImageFrontendFrame out;
  announce(FrontendStage::kPoints);
  if (gray.empty() || gray.type() != CV_8UC1) {
    throw std::invalid_argument("ImageFrontend: the image must be non-empty 8-bit grayscale");
  }
  // One pyramid per image for the point tracker's flow (both ways) and the line tracker's.
  const FlowPyramid pyramid(gray,
                            std::max(options_.points.window_px, options_.lines.flow_window_px),
                            std::max(options_.points.pyramid_levels, options_.lines.flow_levels));
  PointTrackerFrame points = point_tracker_.Track(pyramid);
  out.points = std::move(points.observations);
  out.point_stats = points.stats;
  if (options_.use_lines) {
    announce(FrontendStage::kDetection);
    const double scale = options_.detection_scale;
    cv::Mat small;
    if (scale < 1.0) cv::resize(gray, small, cv::Size(), scale, scale, cv::INTER_AREA);
    LineDetection detection = DetectLineSegments(scale < 1.0 ? small : gray, options_.detector);
    std::vector<Segment2d> segments;
    for (Segment2d s : detection.segments) {
      // Pixel centres: x_full + 0.5 = (x_small + 0.5) / scale.
      if (scale < 1.0) s = ((s.array() + 0.5) / scale - 0.5).matrix();
      if ((s.tail<2>() - s.head<2>()).norm() >= options_.min_segment_px) segments.push_back(s);
    }
    if (options_.max_segments > 0 && static_cast<int>(segments.size()) > options_.max_segments) {
      auto length = [](const Segment2d& s) { return (s.tail<2>() - s.head<2>()).squaredNorm(); };
      std::nth_element(
          segments.begin(), segments.begin() + options_.max_segments, segments.end(),
          [&](const Segment2d& a, const Segment2d& b) { return length(a) > length(b); });
      segments.resize(options_.max_segments);
    }
    out.detection_stats = detection.stats;
    announce(FrontendStage::kLines);
    // The epipolar gate from the point tracker's own RANSAC model of this frame pair (the one
    // FundamentalFromPointTracks would estimate again from the same tracks).
    const std::optional<Eigen::Matrix3d> F_cur_prev =
        points.stats.ransac_inliers >= kMinEpipolarTracks ? points.F_cur_prev : std::nullopt;
    LineTrackerFrame lines = line_tracker_.Track(pyramid, segments, F_cur_prev);
    out.segments = std::move(lines.observations);
    out.line_stats = lines.stats;
  }
  announce(FrontendStage::kDone);
  return out;
}

}  // namespace vision
}  // namespace plucker
