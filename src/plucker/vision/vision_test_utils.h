// Helpers shared by the vision tests (header-only, test use only, not installed).
#pragma once

#include <random>

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

// A textured image: random filled circles of random grey on a mid-grey background, blurred.
inline cv::Mat Texture(int width, int height, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> x(0, width - 1), y(0, height - 1), r(3, 12), g(0, 255);
  cv::Mat image(height, width, CV_8UC1, cv::Scalar(128));
  for (int i = 0; i < width * height / 150; ++i) {
    cv::circle(image, cv::Point(x(rng), y(rng)), r(rng), cv::Scalar(g(rng)), -1, cv::LINE_AA);
  }
  cv::GaussianBlur(image, image, cv::Size(3, 3), 0.8);
  return image;
}

}  // namespace testing
}  // namespace vision
}  // namespace plucker
