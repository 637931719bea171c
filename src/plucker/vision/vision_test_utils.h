// Helpers shared by the vision tests (header-only, test use only, not installed).
#pragma once

#include <opencv2/imgproc.hpp>

namespace plucker {
namespace vision {
namespace testing {

// The image moved by (dx, dy) pixels (bilinear, reflected border): a known optical flow.
inline cv::Mat Shifted(const cv::Mat& image, double dx, double dy) {
  const cv::Matx23d A(1, 0, dx, 0, 1, dy);
  cv::Mat out;
  cv::warpAffine(image, out, A, image.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  return out;
}

}  // namespace testing
}  // namespace vision
}  // namespace plucker
