#include "plucker/io/png_gray.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#ifdef PLUCKER_HAVE_LIBDEFLATE
#include <libdeflate.h>
#endif

namespace plucker {
namespace io {
namespace {

constexpr std::uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr std::uint32_t kMaxSide = 1u << 15;  // larger: declined (the general decoder decides)

std::uint32_t BigEndian32(const std::uint8_t* p) {
  return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) |
         std::uint32_t(p[3]);
}

bool Is(const std::uint8_t* type, const char* name) { return std::memcmp(type, name, 4) == 0; }

// Ancillary chunks that cannot change the decoded gray pixels (text, time, pixel size).
bool Harmless(const std::uint8_t* type) {
  return Is(type, "tEXt") || Is(type, "zTXt") || Is(type, "iTXt") || Is(type, "tIME") ||
         Is(type, "pHYs");
}

// Undoes the row filters of an 8-bit, one-channel image in place: rows of 1 + width bytes (the
// filter type first), written without the type bytes into out. False for an unknown filter.
bool Unfilter(const std::uint8_t* rows, int width, int height, std::uint8_t* out,
              std::size_t out_step) {
  std::vector<std::uint8_t> zero(static_cast<std::size_t>(width), 0);
  const std::uint8_t* up = zero.data();
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* in = rows + static_cast<std::size_t>(y) * (width + 1);
    std::uint8_t* o = out + static_cast<std::size_t>(y) * out_step;
    const std::uint8_t* x = in + 1;
    switch (in[0]) {
      case 0:
        std::memcpy(o, x, width);
        break;
      case 1:
        o[0] = x[0];
        for (int i = 1; i < width; ++i) o[i] = static_cast<std::uint8_t>(x[i] + o[i - 1]);
        break;
      case 2:
        for (int i = 0; i < width; ++i) o[i] = static_cast<std::uint8_t>(x[i] + up[i]);
        break;
      case 3:
        o[0] = static_cast<std::uint8_t>(x[0] + (up[0] >> 1));
        for (int i = 1; i < width; ++i)
          o[i] = static_cast<std::uint8_t>(x[i] + ((o[i - 1] + up[i]) >> 1));
        break;
      case 4: {
        // The predictor: a if pa <= min(pb, pc), else b if pb <= pc, else c; written as two
        // selections without branches (the left neighbour chains the pixels of a row).
        int a = 0, c = 0;  // left and upper left (0 before the first column)
        for (int i = 0; i < width; ++i) {
          const int b = up[i];
          const int pa = std::abs(b - c), pb = std::abs(a - c), pc = std::abs(a + b - 2 * c);
          const int b_or_c = pb <= pc ? b : c;
          const int predicted = pa <= std::min(pb, pc) ? a : b_or_c;
          a = static_cast<std::uint8_t>(x[i] + predicted);
          o[i] = static_cast<std::uint8_t>(a);
          c = b;
        }
        break;
      }
      default:
        return false;
    }
    up = o;
  }
  return true;
}

}  // namespace

#ifdef PLUCKER_HAVE_LIBDEFLATE

bool HasFastGrayPng() { return true; }

std::optional<cv::Mat> DecodeGrayPng(const std::uint8_t* data, std::size_t size) {
  if (size < 8 + 25 || std::memcmp(data, kSignature, 8) != 0) return std::nullopt;
  std::size_t pos = 8;
  std::uint32_t width = 0, height = 0;
  std::vector<std::uint8_t> idat;
  bool header = false, end = false;
  while (!end) {
    if (size - pos < 12) return std::nullopt;  // truncated
    const std::uint32_t length = BigEndian32(data + pos);
    const std::uint8_t* type = data + pos + 4;
    if (length > size - pos - 12) return std::nullopt;
    const std::uint8_t* body = type + 4;
    if (libdeflate_crc32(0, type, length + 4) != BigEndian32(body + length)) return std::nullopt;
    if (Is(type, "IHDR")) {
      // 8-bit depth, colour type 0 (gray), deflate, filter method 0, no interlace.
      if (header || length != 13 || body[8] != 8 || body[9] != 0 || body[10] != 0 ||
          body[11] != 0 || body[12] != 0) {
        return std::nullopt;
      }
      width = BigEndian32(body), height = BigEndian32(body + 4);
      if (width == 0 || height == 0 || width > kMaxSide || height > kMaxSide) return std::nullopt;
      header = true;
    } else if (!header) {
      return std::nullopt;  // IHDR must come first
    } else if (Is(type, "IDAT")) {
      idat.insert(idat.end(), body, body + length);
    } else if (Is(type, "IEND")) {
      end = true;
    } else if (!Harmless(type)) {
      return std::nullopt;
    }
    pos += 12 + length;
  }
  if (idat.empty()) return std::nullopt;
  const std::size_t raw_size = static_cast<std::size_t>(height) * (width + 1);
  std::vector<std::uint8_t> raw(raw_size);
  std::unique_ptr<libdeflate_decompressor, void (*)(libdeflate_decompressor*)> d(
      libdeflate_alloc_decompressor(), libdeflate_free_decompressor);
  if (!d) return std::nullopt;
  std::size_t in_used = 0, out_size = 0;
  if (libdeflate_zlib_decompress_ex(d.get(), idat.data(), idat.size(), raw.data(), raw.size(),
                                    &in_used, &out_size) != LIBDEFLATE_SUCCESS ||
      out_size != raw_size || in_used != idat.size()) {
    return std::nullopt;
  }
  cv::Mat image(static_cast<int>(height), static_cast<int>(width), CV_8UC1);
  if (!Unfilter(raw.data(), static_cast<int>(width), static_cast<int>(height), image.data,
                image.step)) {
    return std::nullopt;
  }
  return image;
}

#else

bool HasFastGrayPng() { return false; }

std::optional<cv::Mat> DecodeGrayPng(const std::uint8_t*, std::size_t) { return std::nullopt; }

#endif

}  // namespace io
}  // namespace plucker
