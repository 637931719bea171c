// Image folders: the images of a folder are its image files in name order; other files (K.txt,
// data.csv, hidden files, sub-folders) are ignored. Image files are those whose extension, in
// any case, is one OpenCV 4.6 of Debian reads: .png .jpg .jpeg .pgm .ppm .pbm .pnm .bmp .tif
// .tiff .webp. Name order is byte order of the file name, so zero-padded numbers (KITTI's
// 000000.png, EuRoC's nanosecond stamps) come in time order.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "plucker/io/io_error.h"

namespace plucker {
namespace io {

// True when the extension of `path` is one of the image extensions above.
bool IsImageFile(const std::string& path);

// The image files of `dir` (full paths) in name order. Throws IoError when `dir` is not a
// folder or holds no image file.
std::vector<std::string> ListImageFiles(const std::string& dir);

// Reads an image as 8-bit grayscale (colour images are converted). `reduction` 1, 2, 4 or 8
// decodes at that fraction of the size (OpenCV's IMREAD_REDUCED_GRAYSCALE_*), e.g. for quick
// tests on large photos. Throws IoError when the file is missing or not a readable image.
cv::Mat ReadGrayImage(const std::string& path, int reduction = 1);

// Why an 8-bit grayscale image holds nothing to track, or "" when it does: black (at least
// `share` of the pixels at or below dark_level), saturated (at or above bright_level) or uniform
// (grey-level standard deviation below min_contrast): a covered lens, an exposure failure.
struct BlankImageOptions {
  double share = 0.98;
  int dark_level = 8, bright_level = 247;
  double min_contrast = 2.0;
};
std::string BlankImageProblem(const cv::Mat& gray, const BlankImageOptions& options = {});

struct ImageSize {
  int width = 0;
  int height = 0;
  bool operator==(const ImageSize& o) const { return width == o.width && height == o.height; }
  bool operator!=(const ImageSize& o) const { return !(*this == o); }
};

// A folder of images that all have the same size, checked once by decoding each image (so an
// unreadable file is found up front). Throws IoError naming the first unreadable file, or the
// first file whose size differs from the first image's (both sizes in the message).
struct ImageFolder {
  std::vector<std::string> files;  // name order
  ImageSize size;                  // of every image
};
ImageFolder OpenImageFolder(const std::string& dir);

// The same check on a given list of files (not empty). Throws IoError.
ImageSize CheckSameImageSize(const std::vector<std::string>& files);

}  // namespace io
}  // namespace plucker
