#include "overlay.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "plucker/io/io_error.h"

namespace plucker {
namespace app {
namespace overlay {
namespace {

cv::Point2d Px(const Eigen::Vector2d& p, double scale) { return {p.x() * scale, p.y() * scale}; }

}  // namespace

cv::Scalar TrackColour(int id) {
  return cv::Scalar((37 * id) % 256, (91 * id + 80) % 256, (53 * id + 160) % 256);
}

cv::Mat Canvas(const cv::Mat& gray, double scale) {
  cv::Mat canvas;
  if (scale == 1.0) {
    cv::cvtColor(gray, canvas, cv::COLOR_GRAY2BGR);
  } else {
    cv::Mat small;
    cv::resize(gray, small, cv::Size(), scale, scale, cv::INTER_AREA);
    cv::cvtColor(small, canvas, cv::COLOR_GRAY2BGR);
  }
  return canvas;
}

void Segment(cv::Mat* canvas, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
             const cv::Scalar& colour, int thickness, double scale, int line_type) {
  cv::line(*canvas, Px(a, scale), Px(b, scale), colour, thickness, line_type);
}

void Dot(cv::Mat* canvas, const Eigen::Vector2d& p, const cv::Scalar& colour, int radius) {
  cv::circle(*canvas, Px(p, 1.0), radius, colour, -1, cv::LINE_AA);
}

void WriteImage(const std::string& path, const cv::Mat& canvas) {
  bool ok = false;
  try {
    ok = cv::imwrite(path, canvas);
  } catch (const cv::Exception& e) {
    throw io::IoError(path, std::string("cannot write the image: ") + e.what());
  }
  if (!ok) throw io::IoError(path, "cannot write the image (folder missing or unknown extension?)");
}

}  // namespace overlay
}  // namespace app
}  // namespace plucker
