// Private helper of the line commands until the io layer's image-folder reader lands (h-camera):
// the image files of a folder in name order, and reading one as 8-bit grayscale.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace plucker {
namespace app {

// Regular files with an image extension (png jpg jpeg bmp pgm ppm pnm tif tiff webp, any case), in
// name order; other files are ignored. Throws std::runtime_error when dir is not a folder.
std::vector<std::string> ListImageFiles(const std::string& dir);

// The image as CV_8UC1 (colour is converted). Throws io::IoError naming the file when it is
// missing or cannot be decoded.
cv::Mat ReadGrayImage(const std::string& path);

}  // namespace app
}  // namespace plucker
