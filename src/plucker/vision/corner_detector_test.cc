#include "plucker/vision/corner_detector.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace plucker {
namespace vision {
namespace {

// The point tracker's kind of mask: a border and discs around existing tracks.
cv::Mat TrackMask(const cv::Size& size, int seed) {
  cv::Mat mask(size, CV_8UC1, cv::Scalar(0));
  mask(cv::Rect(8, 8, size.width - 16, size.height - 16)).setTo(255);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> ux(0, size.width - 1), uy(0, size.height - 1);
  for (int i = 0; i < 150; ++i)
    cv::circle(mask, cv::Point(ux(rng), uy(rng)), 20, cv::Scalar(0), -1);
  return mask;
}

void ExpectSameAsOpenCv(const cv::Mat& gray, const std::string& what) {
  cv::Mat ref, mine;
  cv::cornerMinEigenVal(gray, ref, 3, 3);
  MinEigenResponse3(gray, &mine);
  ASSERT_EQ(ref.size(), mine.size()) << what;
  for (int y = 0; y < ref.rows; ++y) {
    ASSERT_EQ(0, std::memcmp(ref.ptr(y), mine.ptr(y), ref.cols * sizeof(float)))
        << what << ": response differs in row " << y;
  }
  // Only where needed: OpenCV's values there, 0 elsewhere.
  const cv::Mat needed = TrackMask(gray.size(), 3);
  cv::Mat part;
  MinEigenResponse3(gray, &part, needed);
  for (int y = 0; y < ref.rows; ++y) {
    for (int x = 0; x < ref.cols; ++x) {
      const float expected = needed.at<uchar>(y, x) ? ref.at<float>(y, x) : 0.0f;
      ASSERT_EQ(0, std::memcmp(&expected, &part.at<float>(y, x), sizeof(float)))
          << what << ": needed-only response differs at " << x << ", " << y;
    }
  }
  for (int seed = 0; seed < 2; ++seed) {
    const cv::Mat mask = seed == 0 ? cv::Mat() : TrackMask(gray.size(), seed);
    for (double min_distance : {0.0, 20.0}) {
      std::vector<cv::Point2f> expected;
      cv::goodFeaturesToTrack(gray, expected, 150, 0.01, min_distance, mask, 3);
      const std::vector<cv::Point2f> got = ShiTomasiCorners(gray, 150, 0.01, min_distance, mask);
      ASSERT_EQ(expected.size(), got.size()) << what << " mask " << seed;
      for (size_t i = 0; i < got.size(); ++i) {
        EXPECT_EQ(expected[i], got[i]) << what << " corner " << i;
      }
    }
  }
}

TEST(CornerDetector, SameAsOpenCvOnSyntheticImages) {
  cv::Mat noise(97, 131, CV_8UC1);
  cv::randu(noise, 0, 256);
  ExpectSameAsOpenCv(noise, "noise");
  cv::Mat boxes(120, 160, CV_8UC1, cv::Scalar(40));
  cv::rectangle(boxes, cv::Rect(20, 30, 40, 25), cv::Scalar(200), -1);
  cv::rectangle(boxes, cv::Rect(90, 60, 30, 40), cv::Scalar(120), -1);  // ties in the response
  ExpectSameAsOpenCv(boxes, "boxes");
  ExpectSameAsOpenCv(cv::Mat(40, 50, CV_8UC1, cv::Scalar(7)), "flat");
}

TEST(CornerDetector, SameAsOpenCvOnEurocImages) {
  const std::filesystem::path dir =
      std::filesystem::path(PLUCKER_SHARED_DATA_DIR) / "euroc-mh05-clip/mav0/cam0/data";
  if (!std::filesystem::exists(dir)) {
    GTEST_SKIP() << "no EuRoC MH05 clip at " << dir << " (../shared/data)";
  }
  for (const char* name : {"1403638538577829376", "1403638546027829504", "1403638553527829504"}) {
    const cv::Mat gray =
        cv::imread((dir / (std::string(name) + ".png")).string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(gray.empty()) << name;
    ExpectSameAsOpenCv(gray, name);
  }
}

TEST(CornerDetector, RejectsWhatItCannotUse) {
  cv::Mat image(20, 20, CV_8UC1, cv::Scalar(0));
  EXPECT_THROW(ShiTomasiCorners(cv::Mat(), 10, 0.01, 5, cv::Mat()), std::invalid_argument);
  EXPECT_THROW(ShiTomasiCorners(image, 10, 0.01, 5, cv::Mat(10, 10, CV_8UC1)),
               std::invalid_argument);
  EXPECT_THROW(ShiTomasiCorners(image, 10, 1.5, 5, cv::Mat()), std::invalid_argument);
}

}  // namespace
}  // namespace vision
}  // namespace plucker
