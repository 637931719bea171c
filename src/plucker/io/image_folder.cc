#include "plucker/io/image_folder.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "plucker/io/png_gray.h"

namespace plucker {
namespace io {
namespace {

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string SizeText(const ImageSize& s) {
  return std::to_string(s.width) + "x" + std::to_string(s.height);
}

int ReducedFlag(int reduction, const std::string& path) {
  switch (reduction) {
    case 1:
      return cv::IMREAD_GRAYSCALE;
    case 2:
      return cv::IMREAD_REDUCED_GRAYSCALE_2;
    case 4:
      return cv::IMREAD_REDUCED_GRAYSCALE_4;
    case 8:
      return cv::IMREAD_REDUCED_GRAYSCALE_8;
    default:
      throw IoError(path, "image reduction " + std::to_string(reduction) + " is not 1, 2, 4 or 8");
  }
}

// The one-pass decode of an 8-bit gray PNG (png_gray.h), or an empty image for every other file
// (and any problem), which then goes through cv::imread as before.
cv::Mat FastGrayPng(const std::string& path) {
  if (!HasFastGrayPng() || Lower(std::filesystem::path(path).extension().string()) != ".png") {
    return {};
  }
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  const std::streamoff size = in ? static_cast<std::streamoff>(in.tellg()) : -1;
  if (size <= 0) return {};
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size));
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), size)) return {};
  const std::optional<cv::Mat> image = DecodeGrayPng(bytes.data(), bytes.size());
  return image ? *image : cv::Mat();
}

}  // namespace

bool IsImageFile(const std::string& path) {
  static const std::array<const char*, 12> kExtensions = {".png", ".jpg",  ".jpeg", ".pgm",
                                                          ".ppm", ".pbm",  ".pnm",  ".bmp",
                                                          ".tif", ".tiff", ".webp", ".jpe"};
  const std::string ext = Lower(std::filesystem::path(path).extension().string());
  return std::find(kExtensions.begin(), kExtensions.end(), ext) != kExtensions.end();
}

std::vector<std::string> ListImageFiles(const std::string& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) throw IoError(dir, "not a folder");
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || name[0] == '.') continue;
    std::error_code file_ec;
    if (entry.is_regular_file(file_ec) && IsImageFile(name)) files.push_back(entry.path().string());
  }
  if (ec) throw IoError(dir, "cannot list the folder: " + ec.message());
  if (files.empty()) {
    throw IoError(dir, "no image files (.png .jpg .jpeg .pgm .ppm .bmp .tif .tiff .webp)");
  }
  std::sort(files.begin(), files.end());
  return files;
}

cv::Mat ReadGrayImage(const std::string& path, int reduction) {
  const int flag = ReducedFlag(reduction, path);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw IoError(path, "no such image file");
  if (!std::filesystem::is_regular_file(path, ec)) throw IoError(path, "not a regular file");
  cv::Mat image = reduction == 1 ? FastGrayPng(path) : cv::Mat();
  if (!image.empty()) return image;
  try {
    image = cv::imread(path, flag);
  } catch (const cv::Exception& e) {
    throw IoError(path, std::string("cannot decode the image: ") + e.what());
  }
  if (image.empty())
    throw IoError(path, "not a readable image (empty, truncated or unknown format)");
  if (image.type() != CV_8UC1) {
    cv::Mat gray;
    image.convertTo(gray, CV_8U);  // e.g. a 16-bit PNG is read as CV_16U
    image = gray;
  }
  return image;
}

std::string BlankImageProblem(const cv::Mat& gray, const BlankImageOptions& o) {
  if (gray.empty() || gray.type() != CV_8UC1) return "";
  const double n = static_cast<double>(gray.total());
  const double dark = cv::countNonZero(gray <= o.dark_level) / n;
  const double bright = cv::countNonZero(gray >= o.bright_level) / n;
  char buf[160];
  if (dark >= o.share) {
    std::snprintf(buf, sizeof(buf), "black image (%.1f %% of the pixels at or below %d)",
                  100.0 * dark, o.dark_level);
    return buf;
  }
  if (bright >= o.share) {
    std::snprintf(buf, sizeof(buf), "saturated image (%.1f %% of the pixels at or above %d)",
                  100.0 * bright, o.bright_level);
    return buf;
  }
  cv::Scalar mean, stddev;
  cv::meanStdDev(gray, mean, stddev);
  if (stddev[0] < o.min_contrast) {
    std::snprintf(buf, sizeof(buf),
                  "uniform image (grey-level standard deviation %.2f, mean %.1f): nothing to track",
                  stddev[0], mean[0]);
    return buf;
  }
  return "";
}

ImageSize CheckSameImageSize(const std::vector<std::string>& files) {
  if (files.empty()) throw IoError("(no file)", "an empty list of images");
  ImageSize first;
  for (std::size_t i = 0; i < files.size(); ++i) {
    const cv::Mat image = ReadGrayImage(files[i]);
    const ImageSize size{image.cols, image.rows};
    if (i == 0) {
      first = size;
    } else if (size != first) {
      throw IoError(files[i], "image size " + SizeText(size) + " differs from " + SizeText(first) +
                                  " of the first image " + files[0]);
    }
  }
  return first;
}

ImageFolder OpenImageFolder(const std::string& dir) {
  ImageFolder folder;
  folder.files = ListImageFiles(dir);
  folder.size = CheckSameImageSize(folder.files);
  return folder;
}

}  // namespace io
}  // namespace plucker
