#include "image_folder.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

#include "plucker/io/io_error.h"

namespace plucker {
namespace app {

namespace fs = std::filesystem;

std::vector<std::string> ListImageFiles(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw io::IoError(dir, "not a folder");
  static const char* kExtensions[] = {".png", ".jpg", ".jpeg", ".bmp",  ".pgm",
                                      ".ppm", ".pnm", ".tif",  ".tiff", ".webp"};
  std::vector<std::string> files;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    if (!e.is_regular_file(ec)) continue;
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (std::find(std::begin(kExtensions), std::end(kExtensions), ext) != std::end(kExtensions)) {
      files.push_back(e.path().string());
    }
  }
  if (ec) throw io::IoError(dir, "cannot list the folder: " + ec.message());
  std::sort(files.begin(), files.end());
  return files;
}

cv::Mat ReadGrayImage(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw io::IoError(path, "no such file");
  if (!fs::is_regular_file(path, ec)) throw io::IoError(path, "not a regular file");
  cv::Mat image;
  try {
    image = cv::imread(path, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& e) {
    throw io::IoError(path, std::string("cannot decode the image: ") + e.what());
  }
  if (image.empty())
    throw io::IoError(path, "cannot decode the image (unreadable or not an image)");
  if (image.type() != CV_8UC1) image.convertTo(image, CV_8U);
  return image;
}

}  // namespace app
}  // namespace plucker
