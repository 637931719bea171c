#include "plucker/io/calibration_yaml_internal.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace plucker {
namespace io {
namespace internal {

std::string Num(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

std::string ReadText(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw IoError(path, "is a folder, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, "cannot open the file");
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) throw IoError(path, "read error");
  return s.str();
}

double ParseNumber(const std::string& token, const std::string& path, const std::string& what) {
  const char* begin = token.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (end == begin || *end != '\0') {
    throw IoError(path, what + " is not a number: '" + token + "'");
  }
  if (!std::isfinite(v)) throw IoError(path, what + " is not finite: '" + token + "'");
  return v;
}

void ExpectCount(const std::vector<double>& v, std::size_t n, const std::string& path,
                 const std::string& what) {
  if (v.size() != n) {
    throw IoError(path, what + ": expected " + std::to_string(n) + " numbers, found " +
                            std::to_string(v.size()));
  }
}

sensor::Camera CheckedCamera(const sensor::Camera& camera, const std::string& path) {
  const std::string problem = camera.Problem();
  if (!problem.empty()) throw IoError(path, problem);
  return camera;
}

Eigen::Matrix3d CheckedRotation(const Eigen::Matrix3d& R, const std::string& path,
                                const std::string& what, double max_error) {
  const double det = R.determinant();
  const double error = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(det > 0.0) || !(error <= max_error)) {
    throw IoError(path, what + " is not a rotation (max |R^T R - I| = " + Num(error) +
                            ", det = " + Num(det) + ")");
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * svd.matrixV().transpose();
}

int ImageDimension(double v, const std::string& path, const std::string& what) {
  if (!(v >= 1.0) || v > 1e6 || v != std::floor(v)) {
    throw IoError(path, what + " = " + Num(v) + " is not a positive integer");
  }
  return static_cast<int>(v);
}

YAML::Node Required(const YAML::Node& node, const std::string& key, const std::string& path) {
  const YAML::Node child = node[key];
  if (!child.IsDefined() || child.IsNull()) throw IoError(path, "missing key '" + key + "'");
  return child;
}

double YamlNumber(const YAML::Node& node, const std::string& path, const std::string& what) {
  if (!node.IsScalar()) throw IoError(path, what + " is not a number");
  // Through ParseNumber (not yaml-cpp's as<double>) so that ".nan" and "1e400" are rejected and
  // the message shows the text.
  return ParseNumber(node.Scalar(), path, what);
}

std::vector<double> YamlNumbers(const YAML::Node& node, const std::string& key,
                                const std::string& path) {
  if (!node.IsSequence()) throw IoError(path, "'" + key + "' is not a list of numbers");
  std::vector<double> v;
  for (std::size_t i = 0; i < node.size(); ++i) {
    v.push_back(YamlNumber(node[i], path, "'" + key + "' value " + std::to_string(i + 1)));
  }
  return v;
}

std::string YamlString(const YAML::Node& node, const std::string& key, const std::string& path) {
  if (!node.IsScalar()) throw IoError(path, "'" + key + "' is not a string");
  return node.Scalar();
}

YAML::Node ParseYamlMap(std::string text, const std::string& path) {
  // OpenCV's FileStorage writes `%YAML:1.0`, which is not a YAML directive: drop that line.
  if (text.rfind("%YAML:", 0) == 0) {
    const std::size_t eol = text.find('\n');
    text = eol == std::string::npos ? std::string() : text.substr(eol + 1);
  }
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw IoError(path, std::string("not valid YAML: ") + e.what());
  }
  if (!root.IsMap()) throw IoError(path, "not a YAML map of keys");
  return root;
}

}  // namespace internal
}  // namespace io
}  // namespace plucker
