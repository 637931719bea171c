#include "plucker/io/png_gray.h"

#include <gtest/gtest.h>

#include <vector>

#include <opencv2/imgcodecs.hpp>

namespace plucker {
namespace io {
namespace {

// A gray image with smooth ramps, edges and noise: libpng's encoder picks every row filter.
cv::Mat TestImage(int width, int height, unsigned seed) {
  cv::Mat image(height, width, CV_8UC1);
  cv::RNG rng(seed);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const int ramp = (3 * x + 5 * y) % 256;
      const int edge = (x / 9 + y / 7) % 2 ? 90 : 0;
      image.at<std::uint8_t>(y, x) =
          static_cast<std::uint8_t>((ramp + edge + (y % 5 == 0 ? rng.uniform(0, 60) : 0)) % 256);
    }
  }
  return image;
}

std::vector<std::uint8_t> Encode(const cv::Mat& image, std::vector<int> params = {}) {
  std::vector<std::uint8_t> bytes;
  EXPECT_TRUE(cv::imencode(".png", image, bytes, params));
  return bytes;
}

std::optional<cv::Mat> Decode(const std::vector<std::uint8_t>& bytes) {
  return DecodeGrayPng(bytes.data(), bytes.size());
}

TEST(PngGray, SamePixelsAsImdecode) {
  if (!HasFastGrayPng()) GTEST_SKIP() << "built without libdeflate";
  int checked = 0;
  for (const cv::Size size : {cv::Size(1, 1), cv::Size(37, 23), cv::Size(160, 120)}) {
    for (const int level : {0, 1, 9}) {
      for (const int strategy : {cv::IMWRITE_PNG_STRATEGY_DEFAULT, cv::IMWRITE_PNG_STRATEGY_RLE}) {
        const cv::Mat image = TestImage(size.width, size.height, 7u * checked + 1u);
        const std::vector<std::uint8_t> bytes =
            Encode(image, {cv::IMWRITE_PNG_COMPRESSION, level, cv::IMWRITE_PNG_STRATEGY, strategy});
        const cv::Mat reference = cv::imdecode(bytes, cv::IMREAD_GRAYSCALE);
        ASSERT_EQ(cv::countNonZero(reference != image), 0);
        const std::optional<cv::Mat> fast = Decode(bytes);
        ASSERT_TRUE(fast) << size << " level " << level;
        ASSERT_EQ(fast->type(), CV_8UC1);
        ASSERT_EQ(fast->size(), image.size());
        EXPECT_EQ(cv::countNonZero(*fast != reference), 0) << size << " level " << level;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 18);
}

TEST(PngGray, DeclinesOtherFormatsAndBrokenFiles) {
  const cv::Mat gray = TestImage(40, 30, 3);
  cv::Mat color, deep;
  cv::merge(std::vector<cv::Mat>{gray, gray, gray}, color);
  gray.convertTo(deep, CV_16U, 200.0);
  EXPECT_FALSE(Decode(Encode(color)));  // colour type 2
  EXPECT_FALSE(Decode(Encode(deep)));   // 16 bits
  const std::vector<std::uint8_t> good = Encode(gray);
  ASSERT_EQ(Decode(good).has_value(), HasFastGrayPng());
  std::vector<std::uint8_t> truncated(good.begin(), good.begin() + good.size() / 2);
  EXPECT_FALSE(Decode(truncated));
  std::vector<std::uint8_t> bad_crc = good;
  bad_crc[40] ^= 0x5a;  // inside the first IDAT (after the 33 bytes of signature and IHDR)
  EXPECT_FALSE(Decode(bad_crc));
  std::vector<std::uint8_t> not_png = good;
  not_png[1] = 'Q';
  EXPECT_FALSE(Decode(not_png));
  EXPECT_FALSE(DecodeGrayPng(good.data(), 0));
}

}  // namespace
}  // namespace io
}  // namespace plucker
