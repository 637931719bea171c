#include "plucker/vision/image_frontend.h"

#include <optional>

namespace plucker {
namespace vision {

ImageFrontend::ImageFrontend(const PinholeIntrinsics& K, const ImageFrontendOptions& options)
    : K_(K), options_(options), point_tracker_(options.points, K), line_tracker_(options.lines) {}

ImageFrontendFrame ImageFrontend::Process(const cv::Mat& gray, const FrontendObserver& observer) {
  auto announce = [&](FrontendStage s) {
    if (observer) observer(s);
  };
  ImageFrontendFrame out;
  announce(FrontendStage::kPoints);
  PointTrackerFrame points = point_tracker_.Track(gray);
  out.points = std::move(points.observations);
  out.point_stats = points.stats;
  if (options_.use_lines) {
    announce(FrontendStage::kDetection);
    LineDetection detection = DetectLineSegments(gray, options_.detector);
    std::vector<Segment2d> segments;
    for (const Segment2d& s : detection.segments) {
      if ((s.tail<2>() - s.head<2>()).norm() >= options_.min_segment_px) segments.push_back(s);
    }
    out.detection_stats = detection.stats;
    announce(FrontendStage::kLines);
    const std::optional<Eigen::Matrix3d> F_cur_prev =
        previous_points_.empty() ? std::nullopt
                                 : FundamentalFromPointTracks(previous_points_, out.points, K_);
    LineTrackerFrame lines = line_tracker_.Track(gray, segments, F_cur_prev);
    out.segments = std::move(lines.observations);
    out.line_stats = lines.stats;
  }
  previous_points_ = out.points;
  announce(FrontendStage::kDone);
  return out;
}

}  // namespace vision
}  // namespace plucker
