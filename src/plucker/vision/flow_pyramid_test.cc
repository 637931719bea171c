#include "plucker/vision/flow_pyramid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "plucker/vision/vision_test_utils.h"

namespace plucker {
namespace vision {
namespace {

// Flow on pyramids built once (with a larger window and more levels than the flow uses) equals
// OpenCV's flow on the two images, in both directions, and follows the known shift.
TEST(FlowPyramid, SameFlowAsOnTheImages) {
  const cv::Mat a = testing::Texture(320, 240, 3);
  const cv::Mat b = testing::Shifted(a, 3.4, -2.2);
  std::vector<cv::Point2f> points;
  cv::goodFeaturesToTrack(a, points, 150, 0.01, 10);
  ASSERT_GT(points.size(), 100u);
  const FlowPyramid pa(a, 15, 4), pb(b, 15, 4);
  EXPECT_EQ(pa.size(), a.size());
  for (const int window : {11, 15}) {
    std::vector<cv::Point2f> shared, direct;
    std::vector<unsigned char> status_shared, status_direct;
    std::vector<float> error;
    PyramidFlow(pa, pb, points, window, 3, &shared, &status_shared);
    cv::calcOpticalFlowPyrLK(a, b, points, direct, status_direct, error, cv::Size(window, window),
                             3);
    ASSERT_EQ(shared.size(), points.size());
    int compared = 0, on_shift = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (!status_shared[i] || !status_direct[i]) continue;
      ++compared;
      EXPECT_LT(std::hypot(shared[i].x - direct[i].x, shared[i].y - direct[i].y), 1e-3);
      on_shift +=
          std::hypot(shared[i].x - points[i].x - 3.4f, shared[i].y - points[i].y + 2.2f) < 0.1;
    }
    EXPECT_GT(compared, 100) << "window " << window;
    EXPECT_GT(on_shift, 90) << "window " << window;
  }
  // Back again on the same pyramids.
  std::vector<cv::Point2f> moved, back;
  std::vector<unsigned char> status, back_status;
  PyramidFlow(pa, pb, points, 11, 4, &moved, &status);
  PyramidFlow(pb, pa, moved, 11, 4, &back, &back_status);
  int returned = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    returned += status[i] && back_status[i] &&
                std::hypot(back[i].x - points[i].x, back[i].y - points[i].y) < 0.1;
  }
  EXPECT_GT(returned, 90);
}

TEST(FlowPyramid, BadInput) {
  const cv::Mat a = testing::Texture(160, 120, 1);
  EXPECT_THROW(FlowPyramid(cv::Mat(), 11, 3), std::invalid_argument);
  EXPECT_THROW(FlowPyramid(cv::Mat(10, 10, CV_32F), 11, 3), std::invalid_argument);
  EXPECT_THROW(FlowPyramid(a, 2, 3), std::invalid_argument);
  EXPECT_THROW(FlowPyramid(a, 11, -1), std::invalid_argument);
  const FlowPyramid p(a, 11, 3), q(testing::Texture(200, 120, 2), 11, 3);
  std::vector<cv::Point2f> moved;
  std::vector<unsigned char> status;
  const std::vector<cv::Point2f> points = {{50.f, 50.f}};
  EXPECT_THROW(PyramidFlow(p, q, points, 11, 3, &moved, &status), std::invalid_argument);
  EXPECT_THROW(PyramidFlow(p, p, points, 15, 3, &moved, &status), std::invalid_argument);
  EXPECT_THROW(PyramidFlow(p, FlowPyramid(), points, 11, 3, &moved, &status),
               std::invalid_argument);
  PyramidFlow(p, p, {}, 11, 3, &moved, &status);
  EXPECT_TRUE(moved.empty());
}

}  // namespace
}  // namespace vision
}  // namespace plucker
