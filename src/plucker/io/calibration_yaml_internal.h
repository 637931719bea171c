// Field readers shared by the calibration readers (camera_calibration.cc, kalibr_calibration.cc):
// every one throws IoError naming the file (`path`) and the key or value. Not part of the
// library API (not installed).
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <string>
#include <vector>

#include "plucker/io/io_error.h"
#include "plucker/sensor/camera.h"

namespace plucker {
namespace io {
namespace internal {

std::string Num(double v);  // 10 significant digits, for messages

// The whole file; IoError when it is a folder, missing or unreadable.
std::string ReadText(const std::string& path);

// A number token (strtod, the whole token); IoError when not a number or not finite.
double ParseNumber(const std::string& token, const std::string& path, const std::string& what);

// The nearest rotation (SVD) of R when max |R^T R - I| <= max_error and det R > 0; otherwise
// IoError "WHAT is not a rotation (...)".
Eigen::Matrix3d CheckedRotation(const Eigen::Matrix3d& R, const std::string& path,
                                const std::string& what, double max_error);

// IoError "WHAT: expected N numbers, found M" unless v has n values.
void ExpectCount(const std::vector<double>& v, std::size_t n, const std::string& path,
                 const std::string& what);

// An image width or height: a positive integer up to 1e6.
int ImageDimension(double v, const std::string& path, const std::string& what);

// The camera when camera.Problem() is empty, otherwise IoError with the problem.
sensor::Camera CheckedCamera(const sensor::Camera& camera, const std::string& path);

// ---- YAML ----
YAML::Node Required(const YAML::Node& node, const std::string& key, const std::string& path);
double YamlNumber(const YAML::Node& node, const std::string& path, const std::string& what);
std::vector<double> YamlNumbers(const YAML::Node& node, const std::string& key,
                                const std::string& path);
std::string YamlString(const YAML::Node& node, const std::string& key, const std::string& path);
// The text parsed as a YAML map (OpenCV's `%YAML:1.0` first line dropped); `path` names it.
YAML::Node ParseYamlMap(std::string text, const std::string& path);

}  // namespace internal
}  // namespace io
}  // namespace plucker
