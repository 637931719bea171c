// A fast path for the commonest image of the datasets (EuRoC, KITTI, TUM): an 8-bit grayscale,
// non-interlaced PNG, decoded in one pass (the zlib stream inflated whole by libdeflate, then the
// five PNG row filters undone), about twice as fast as the row-by-row decoder behind cv::imread.
// Anything else (colour, palette, 16 bits, interlace, transparency, gamma or any chunk that could
// change the pixels, a bad CRC, a truncated or inconsistent stream) is declined, and the caller
// decodes the file as before (image_folder.cc), so that errors and every other format are
// unchanged. The pixels are the same bytes: PNG is lossless (tested against cv::imread).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

#include <opencv2/core.hpp>

namespace plucker {
namespace io {

// True when libdeflate was found at build time (otherwise DecodeGrayPng always declines).
bool HasFastGrayPng();

// The image of the PNG file bytes data[0, size) as CV_8UC1, or nullopt when declined (above).
std::optional<cv::Mat> DecodeGrayPng(const std::uint8_t* data, std::size_t size);

}  // namespace io
}  // namespace plucker
