#include "plucker/vision/point_tracker.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/LU>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "plucker/vision/corner_detector.h"

namespace plucker {
namespace vision {
namespace {

void CheckOptions(const PointTrackerOptions& o) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("PointTracker: " + what); };
  if (o.target_count < 1) fail("target_count must be >= 1");
  if (!(o.detect_below_share > 0 && o.detect_below_share <= 1)) {
    fail("detect_below_share must be in (0, 1]");
  }
  if (!(o.min_distance_px >= 0)) fail("min_distance_px must be >= 0");
  if (!(o.quality_level > 0 && o.quality_level < 1)) fail("quality_level must be in (0, 1)");
  if (o.block_size < 1) fail("block_size must be >= 1");
  if (o.border_px < 0) fail("border_px must be >= 0");
  if (o.window_px < 3) fail("window_px must be >= 3");
  if (o.pyramid_levels < 0) fail("pyramid_levels must be >= 0");
  if (!(o.max_forward_backward_px > 0)) fail("max_forward_backward_px must be > 0");
  if (!(o.ransac_threshold_px > 0)) fail("ransac_threshold_px must be > 0");
  if (!(o.ransac_confidence > 0 && o.ransac_confidence < 1)) {
    fail("ransac_confidence must be in (0, 1)");
  }
  if (o.min_ransac_points < 8) fail("min_ransac_points must be >= 8");
}

bool Inside(const cv::Point2f& p, const cv::Mat& image, int border) {
  return std::isfinite(p.x) && std::isfinite(p.y) && p.x >= border && p.y >= border &&
         p.x <= image.cols - 1 - border && p.y <= image.rows - 1 - border;
}

}  // namespace

std::optional<Eigen::Matrix3d> FundamentalOfModel(const cv::Mat& model,
                                                  const std::optional<PinholeIntrinsics>& K) {
  if (model.rows != 3 || model.cols != 3 || model.type() != CV_64F) return std::nullopt;
  Eigen::Matrix3d M;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) M(r, c) = model.at<double>(r, c);
  }
  if (K) {
    const Eigen::Matrix3d K_inv = K->K().inverse();
    M = K_inv.transpose() * M * K_inv;
  }
  if (!M.allFinite() || !(M.norm() > 0)) return std::nullopt;
  return M / M.norm();
}

cv::Mat EpipolarModel(cv::InputArray p0, cv::InputArray p1,
                      const std::optional<PinholeIntrinsics>& K, double threshold_px,
                      double confidence, cv::OutputArray inliers) {
  if (K) {
    const cv::Matx33d Kcv(K->fx, 0, K->cx, 0, K->fy, K->cy, 0, 0, 1);
    return cv::findEssentialMat(p0, p1, Kcv, cv::RANSAC, confidence, threshold_px, inliers);
  }
  return cv::findFundamentalMat(p0, p1, cv::FM_RANSAC, threshold_px, confidence, inliers);
}

PointTracker::PointTracker(const PointTrackerOptions& options,
                           const std::optional<PinholeIntrinsics>& K)
    : options_(options), K_(K) {
  CheckOptions(options_);
  if (K_ && !K_->IsValid()) throw std::invalid_argument("PointTracker: invalid intrinsics");
}

PointTrackerFrame PointTracker::Track(const cv::Mat& image) {
  if (image.empty()) throw std::invalid_argument("PointTracker: empty image");
  if (image.type() != CV_8UC1) throw std::invalid_argument("PointTracker: not 8-bit grayscale");
  return Track(FlowPyramid(image, options_.window_px, options_.pyramid_levels));
}

PointTrackerFrame PointTracker::Track(const FlowPyramid& pyramid) {
  if (pyramid.empty()) throw std::invalid_argument("PointTracker: empty image");
  const cv::Mat& image = pyramid.image();
  if (image.type() != CV_8UC1) throw std::invalid_argument("PointTracker: not 8-bit grayscale");
  if (pyramid.window_px() < options_.window_px) {
    throw std::invalid_argument("PointTracker: pyramid built for a window of " +
                                std::to_string(pyramid.window_px()) + " px < window_px " +
                                std::to_string(options_.window_px));
  }
  if (!previous_.empty() && image.size() != previous_.size()) {
    throw std::invalid_argument("PointTracker: image of " + std::to_string(image.cols) + "x" +
                                std::to_string(image.rows) + " after " +
                                std::to_string(previous_.size().width) + "x" +
                                std::to_string(previous_.size().height));
  }
  PointTrackerFrame out;
  out.frame = frame_++;
  out.stats.previous = static_cast<int>(points_.size());
  if (!points_.empty()) FlowAndCheck(pyramid, &out);
  Detect(image, &out);
  previous_ = pyramid;
  points_.clear();
  ids_.clear();
  for (const sensor::PointObservation& o : out.observations) {
    points_.emplace_back(static_cast<float>(o.uv.x()), static_cast<float>(o.uv.y()));
    ids_.push_back(o.point_id);
  }
  return out;
}

void PointTracker::FlowAndCheck(const FlowPyramid& pyramid, PointTrackerFrame* out) {
  const cv::Mat& image = pyramid.image();
  std::vector<cv::Point2f> next, back;
  std::vector<unsigned char> status, back_status;
  PyramidFlow(previous_, pyramid, points_, options_.window_px, options_.pyramid_levels, &next,
              &status);
  PyramidFlow(pyramid, previous_, next, options_.window_px, options_.pyramid_levels, &back,
              &back_status);
  std::vector<cv::Point2f> prev_kept;
  PointTrackerStats& stats = out->stats;
  for (std::size_t i = 0; i < points_.size(); ++i) {
    if (!status[i] || !Inside(next[i], image, options_.border_px)) {
      ++stats.flow_failed;
      continue;
    }
    const cv::Point2f round_trip = back[i] - points_[i];
    if (!back_status[i] ||
        !(std::hypot(round_trip.x, round_trip.y) <= options_.max_forward_backward_px)) {
      ++stats.forward_backward_failed;
      continue;
    }
    prev_kept.push_back(points_[i]);
    sensor::PointObservation o;
    o.frame = out->frame;
    o.point_id = ids_[i];
    o.uv = Eigen::Vector2d(next[i].x, next[i].y);
    out->observations.push_back(o);
  }
  RejectEpipolarOutliers(&prev_kept, out);
  stats.tracked = static_cast<int>(out->observations.size());
}

void PointTracker::RejectEpipolarOutliers(std::vector<cv::Point2f>* prev_points,
                                          PointTrackerFrame* out) {
  std::vector<sensor::PointObservation>& obs = out->observations;
  if (static_cast<int>(obs.size()) < options_.min_ransac_points) return;
  std::vector<cv::Point2f> next;
  for (const sensor::PointObservation& o : obs) {
    next.emplace_back(static_cast<float>(o.uv.x()), static_cast<float>(o.uv.y()));
  }
  std::vector<unsigned char> inlier;
  const cv::Mat model = EpipolarModel(*prev_points, next, K_, options_.ransac_threshold_px,
                                      options_.ransac_confidence, inlier);
  if (model.empty() || inlier.size() != obs.size()) return;  // no model: keep all, not run
  out->stats.ransac_run = true;
  out->F_cur_prev = FundamentalOfModel(model, K_);
  std::size_t kept = 0;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    if (!inlier[i]) {
      ++out->stats.ransac_outliers;
      continue;
    }
    obs[kept] = obs[i];
    (*prev_points)[kept] = (*prev_points)[i];
    ++kept;
  }
  out->stats.ransac_inliers = static_cast<int>(kept);
  obs.resize(kept);
  prev_points->resize(kept);
}

void PointTracker::Detect(const cv::Mat& image, PointTrackerFrame* out) {
  const int tracked = static_cast<int>(out->observations.size());
  const int wanted = options_.target_count - tracked;
  if (wanted <= 0 || tracked >= options_.detect_below_share * options_.target_count) return;
  const int b = options_.border_px;
  if (image.cols <= 2 * b + 1 || image.rows <= 2 * b + 1) return;
  out->stats.detection_run = true;
  cv::Mat mask(image.size(), CV_8UC1, cv::Scalar(0));
  mask(cv::Rect(b, b, image.cols - 2 * b, image.rows - 2 * b)).setTo(255);
  const int radius = static_cast<int>(std::ceil(options_.min_distance_px));
  for (const sensor::PointObservation& o : out->observations) {
    cv::circle(mask, cv::Point(cvRound(o.uv.x()), cvRound(o.uv.y())), radius, cv::Scalar(0), -1);
  }
  // ShiTomasiCorners: goodFeaturesToTrack's corners bit for bit at less cost (block size 3).
  std::vector<cv::Point2f> corners;
  if (options_.block_size == 3) {
    corners =
        ShiTomasiCorners(image, wanted, options_.quality_level, options_.min_distance_px, mask);
  } else {
    cv::goodFeaturesToTrack(image, corners, wanted, options_.quality_level,
                            options_.min_distance_px, mask, options_.block_size);
  }
  for (const cv::Point2f& c : corners) {
    sensor::PointObservation o;
    o.frame = out->frame;
    o.point_id = next_id_++;
    o.uv = Eigen::Vector2d(c.x, c.y);
    out->observations.push_back(o);
  }
  out->stats.detected = static_cast<int>(corners.size());
}

}  // namespace vision
}  // namespace plucker
