#include "plucker/vision/flow_pyramid.h"

#include <algorithm>
#include <stdexcept>

#include <opencv2/video/tracking.hpp>

namespace plucker {
namespace vision {

FlowPyramid::FlowPyramid(const cv::Mat& image, int window_px, int max_level)
    : window_px_(window_px), max_level_(max_level) {
  if (image.empty() || image.type() != CV_8UC1) {
    throw std::invalid_argument("FlowPyramid: the image must be non-empty 8-bit grayscale");
  }
  if (window_px < 3 || max_level < 0) {
    throw std::invalid_argument("FlowPyramid: window_px must be >= 3 and max_level >= 0");
  }
  // An own (padded) copy of the image: the caller may reuse its buffer.
  const int built = cv::buildOpticalFlowPyramid(image, levels_, cv::Size(window_px, window_px),
                                                max_level, /*withDerivatives=*/true,
                                                cv::BORDER_REFLECT_101, cv::BORDER_CONSTANT,
                                                /*tryReuseInputImage=*/false);
  max_level_ = std::min(max_level, built);
  image_ = levels_.front();
}

void PyramidFlow(const FlowPyramid& from, const FlowPyramid& to,
                 const std::vector<cv::Point2f>& points, int window_px, int max_level,
                 std::vector<cv::Point2f>* moved, std::vector<unsigned char>* status,
                 int max_iterations) {
  if (from.empty() || to.empty() || from.size() != to.size()) {
    throw std::invalid_argument("PyramidFlow: empty pyramids or images of different sizes");
  }
  if (max_iterations < 1) throw std::invalid_argument("PyramidFlow: max_iterations must be >= 1");
  if (window_px < 3 || window_px > std::min(from.window_px(), to.window_px())) {
    throw std::invalid_argument("PyramidFlow: window larger than the pyramids were built for");
  }
  moved->clear();
  status->clear();
  if (points.empty()) return;
  const int levels = std::max(0, std::min({max_level, from.max_level(), to.max_level()}));
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(
      from.levels(), to.levels(), points, *moved, *status, error, cv::Size(window_px, window_px),
      levels,
      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, max_iterations, 0.01));
}

}  // namespace vision
}  // namespace plucker
