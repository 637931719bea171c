#include "plucker/vision/undistort.h"

#include <stdexcept>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace plucker {
namespace vision {
namespace {

cv::Matx33d ToCv(const PinholeIntrinsics& K) {
  return cv::Matx33d(K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1);
}

bool SameIntrinsics(const PinholeIntrinsics& a, const PinholeIntrinsics& b) {
  return a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy;
}

std::string SizeText(int width, int height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

}  // namespace

Undistorter::Undistorter(const sensor::Camera& camera, const UndistorterOptions& options)
    : raw_(camera) {
  const std::string problem = camera.Problem();
  if (!problem.empty()) throw std::invalid_argument("Undistorter: camera: " + problem);
  ideal_ = camera.Undistorted();
  if (options.output_K) ideal_.K = *options.output_K;
  if (options.output_width > 0) ideal_.width = options.output_width;
  if (options.output_height > 0) ideal_.height = options.output_height;
  const std::string ideal_problem = ideal_.Problem();
  if (!ideal_problem.empty()) {
    throw std::invalid_argument("Undistorter: output pinhole: " + ideal_problem);
  }
  identity_ = camera.IsPinhole() && SameIntrinsics(camera.K, ideal_.K) &&
              camera.width == ideal_.width && camera.height == ideal_.height;
  if (identity_) return;
  const cv::Size size(ideal_.width, ideal_.height);
  if (camera.model == sensor::CameraModel::kEquidistant) {  // the same model and order as KB
    const EquidistantDistortion& e = camera.equidistant;
    const cv::Vec4d dist(e.k1, e.k2, e.k3, e.k4);
    cv::fisheye::initUndistortRectifyMap(ToCv(camera.K), dist, cv::Matx33d::eye(), ToCv(ideal_.K),
                                         size, CV_16SC2, map1_, map2_);
    return;
  }
  const RadTanDistortion& d = camera.distortion;
  const cv::Mat dist = (cv::Mat_<double>(1, 5) << d.k1, d.k2, d.p1, d.p2, d.k3);
  cv::initUndistortRectifyMap(ToCv(camera.K), dist, cv::noArray(), ToCv(ideal_.K), size, CV_16SC2,
                              map1_, map2_);
}

cv::Mat Undistorter::Undistort(const cv::Mat& raw) const {
  if (raw.empty()) throw std::invalid_argument("Undistorter: empty image");
  if (raw.cols != raw_.width || raw.rows != raw_.height) {
    throw std::invalid_argument("Undistorter: image of " + SizeText(raw.cols, raw.rows) +
                                " for a camera of " + SizeText(raw_.width, raw_.height));
  }
  if (identity_) return raw;
  cv::Mat out;
  cv::remap(raw, out, map1_, map2_, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar::all(0));
  return out;
}

std::optional<Eigen::Vector2d> Undistorter::IdealFromRaw(const Eigen::Vector2d& uv_raw) const {
  const auto xn = raw_.PixelToNormalized(uv_raw);
  if (!xn) return std::nullopt;
  return ideal_.K.ToPixel<double>(*xn);
}

std::optional<Eigen::Vector2d> Undistorter::RawFromIdeal(const Eigen::Vector2d& uv_ideal) const {
  if (!uv_ideal.allFinite()) return std::nullopt;
  const Eigen::Vector2d uv = raw_.NormalizedToPixel(ideal_.K.ToNormalized<double>(uv_ideal));
  if (!uv.allFinite()) return std::nullopt;
  return uv;
}

}  // namespace vision
}  // namespace plucker
