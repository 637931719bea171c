// libFuzzer target: the one-pass gray PNG decoder (io/png_gray.h) against OpenCV's decoder.
// Before decoding, every chunk's CRC is recomputed, so that mutations reach the inflate and the
// row filters instead of stopping at the first CRC check. Whenever both decoders accept an
// input, their pixels must be the same. Built as a fuzzer with -DPLUCKER_BUILD_FUZZERS=ON
// (clang, cmake/Fuzzers.cmake); io/fuzz_test.cc runs the same entry point as a unit test.
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "plucker/io/fuzz_util.h"
#include "plucker/io/png_gray.h"

namespace plucker {
namespace io {
namespace fuzz {

std::vector<std::string> PngGraySeeds() {
  std::vector<std::string> seeds;
  cv::Mat image(13, 17, CV_8UC1);
  for (int r = 0; r < image.rows; ++r)
    for (int c = 0; c < image.cols; ++c) image.at<std::uint8_t>(r, c) = (r * 37 + c * c * 11) % 256;
  for (int strategy = 0; strategy <= 4; ++strategy) {
    std::vector<std::uint8_t> png;
    cv::imencode(".png", image, png, {cv::IMWRITE_PNG_STRATEGY, strategy});
    seeds.emplace_back(png.begin(), png.end());
  }
  return seeds;
}

namespace {

std::uint32_t Crc32(const std::uint8_t* p, std::size_t n) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}

// Rewrites the CRC of every whole chunk after the 8-byte signature.
void RepairCrcs(std::vector<std::uint8_t>* b) {
  std::size_t at = 8;
  while (at + 12 <= b->size()) {
    const std::uint8_t* p = b->data() + at;
    const std::uint64_t length = (std::uint64_t{p[0]} << 24) | (p[1] << 16) | (p[2] << 8) | p[3];
    if (length > b->size() - at - 12) return;
    const std::uint32_t crc = Crc32(p + 4, static_cast<std::size_t>(length) + 4);
    std::uint8_t* q = b->data() + at + 8 + length;
    q[0] = crc >> 24, q[1] = (crc >> 16) & 0xFF, q[2] = (crc >> 8) & 0xFF, q[3] = crc & 0xFF;
    at += 12 + static_cast<std::size_t>(length);
  }
}

}  // namespace

int PngGrayOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> bytes(data, data + size);
  RepairCrcs(&bytes);
  const std::optional<cv::Mat> fast = DecodeGrayPng(bytes.data(), bytes.size());
  if (!fast) return 0;
  Check(fast->type() == CV_8UC1 && !fast->empty(), "an accepted PNG decoded to no gray image");
  // OpenCV (libpng) may refuse what the fast path accepts (e.g. trailing bytes); where both
  // decode, the pixels must be the same.
  const cv::Mat reference = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  if (reference.empty()) return 0;
  Check(reference.type() == CV_8UC1 && reference.size() == fast->size() &&
            cv::countNonZero(reference != *fast) == 0,
        "the fast decoder's pixels differ from OpenCV's");
  return 0;
}

}  // namespace fuzz
}  // namespace io
}  // namespace plucker

PLUCKER_FUZZ_TARGET("png_gray", PngGraySeeds, PngGrayOneInput)
