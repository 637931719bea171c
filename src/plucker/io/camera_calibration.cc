#include "plucker/io/camera_calibration.h"

#include "plucker/io/calibration_yaml_internal.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace plucker {
namespace io {
namespace {

using namespace internal;  // NOLINT(build/namespaces): the shared field readers

constexpr double kMaxOrthonormalityError = 1e-3;  // max |R^T R - I| accepted (then repaired)
constexpr double kMaxRelativeSkew = 1e-9;         // |K(0,1)| / fx treated as zero skew

// All whitespace-separated numbers of `text`; `what` names them in errors.
std::vector<double> ParseNumbers(const std::string& text, const std::string& path,
                                 const std::string& what) {
  std::istringstream in(text);
  std::vector<double> values;
  std::string token;
  while (in >> token) {
    values.push_back(
        ParseNumber(token, path, what + " value " + std::to_string(values.size() + 1)));
  }
  return values;
}

// K from a 3x3 upper-left block: zero skew, last row (0, 0, 1).
PinholeIntrinsics IntrinsicsFrom(const Eigen::Matrix3d& K, const std::string& path,
                                 const std::string& what) {
  if (!(K(0, 0) > 0) || !(K(1, 1) > 0)) {
    throw IoError(path, what + ": non-positive focal length (fx = " + Num(K(0, 0)) +
                            ", fy = " + Num(K(1, 1)) + ")");
  }
  if (std::abs(K(0, 1)) > kMaxRelativeSkew * K(0, 0) || K(1, 0) != 0.0) {
    throw IoError(path, what + ": non-zero skew (" + Num(K(0, 1)) +
                            "); only zero-skew pinholes are supported");
  }
  if (K(2, 0) != 0.0 || K(2, 1) != 0.0 || K(2, 2) != 1.0) {
    throw IoError(path, what + ": last row is not (0, 0, 1)");
  }
  return PinholeIntrinsics{K(0, 0), K(1, 1), K(0, 2), K(1, 2)};
}

Eigen::Matrix3d RowMajor3x3(const std::vector<double>& v, std::size_t offset) {
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m(r, c) = v[offset + 3 * r + c];
  }
  return m;
}

// ---- EuRoC YAML ----

YAML::Node LoadYaml(const std::string& path) { return ParseYamlMap(ReadText(path), path); }

SE3d EurocTransform(const YAML::Node& root, const std::string& path) {
  const YAML::Node t_bs = Required(root, "T_BS", path);
  if (!t_bs.IsMap()) throw IoError(path, "'T_BS' is not a map with rows, cols and data");
  const double rows = YamlNumber(Required(t_bs, "rows", path), path, "'T_BS' rows");
  const double cols = YamlNumber(Required(t_bs, "cols", path), path, "'T_BS' cols");
  if (rows != 4 || cols != 4) {
    throw IoError(path, "'T_BS' is " + Num(rows) + "x" + Num(cols) + ", expected 4x4");
  }
  const std::vector<double> v = YamlNumbers(Required(t_bs, "data", path), "T_BS data", path);
  ExpectCount(v, 16, path, "'T_BS' data");
  if (v[12] != 0 || v[13] != 0 || v[14] != 0 || v[15] != 1) {
    throw IoError(path, "'T_BS' last row is not (0, 0, 0, 1)");
  }
  Eigen::Matrix3d R;
  R << v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10];
  return SE3d(CheckedRotation(R, path, "'T_BS' rotation", kMaxOrthonormalityError),
              Eigen::Vector3d(v[3], v[7], v[11]));
}

}  // namespace

KittiCalibration ReadKittiCalibration(const std::string& path, int width, int height,
                                      const std::string& key) {
  std::istringstream in(ReadText(path));
  std::string line;
  const std::string prefix = key + ":";
  while (std::getline(in, line)) {
    if (line.rfind(prefix, 0) != 0) continue;
    const std::vector<double> v = ParseNumbers(line.substr(prefix.size()), path, key);
    ExpectCount(v, 12, path, key);
    KittiCalibration calib;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) calib.P(r, c) = v[4 * r + c];
    }
    calib.camera.K = IntrinsicsFrom(calib.P.leftCols<3>(), path, key);
    calib.camera.width = width;
    calib.camera.height = height;
    calib.camera = CheckedCamera(calib.camera, path);
    return calib;
  }
  throw IoError(path, "no '" + prefix + "' line (a KITTI calib.txt has P0: .. P3:)");
}

sensor::Camera ReadStrechaIntrinsics(const std::string& path, int width, int height) {
  const std::vector<double> v = ParseNumbers(ReadText(path), path, "K");
  ExpectCount(v, 9, path, "K (3x3)");
  sensor::Camera camera;
  camera.K = IntrinsicsFrom(RowMajor3x3(v, 0), path, "K");
  camera.width = width;
  camera.height = height;
  return CheckedCamera(camera, path);
}

StrechaCamera ReadStrechaCamera(const std::string& path) {
  const std::vector<double> v = ParseNumbers(ReadText(path), path, ".camera");
  ExpectCount(v, 26, path, "K 3x3, distortion 3, R 3x3, C 3, width height");
  StrechaCamera result;
  sensor::Camera& camera = result.camera;
  camera.K = IntrinsicsFrom(RowMajor3x3(v, 0), path, "K");
  camera.distortion.k1 = v[9];
  camera.distortion.k2 = v[10];
  camera.distortion.k3 = v[11];
  const Eigen::Matrix3d R = CheckedRotation(RowMajor3x3(v, 12), path, "R", kMaxOrthonormalityError);
  const Eigen::Vector3d C(v[21], v[22], v[23]);
  camera.width = ImageDimension(v[24], path, "width");
  camera.height = ImageDimension(v[25], path, "height");
  camera = CheckedCamera(camera, path);
  result.T_w_c = SE3d(R, C);
  return result;
}

std::vector<std::string> ListStrechaCameraFiles(const std::string& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) throw IoError(dir, "not a folder");
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    if (entry.is_regular_file(ec) && entry.path().extension() == ".camera") {
      files.push_back(entry.path().string());
    }
  }
  if (ec) throw IoError(dir, "cannot list the folder: " + ec.message());
  if (files.empty()) throw IoError(dir, "no *.camera files");
  std::sort(files.begin(), files.end());
  return files;
}

namespace {

EurocCamera ParseEurocCamera(const YAML::Node& root, const std::string& path) {
  if (root["sensor_type"].IsDefined()) {
    const std::string type = YamlString(root["sensor_type"], "sensor_type", path);
    if (type != "camera") throw IoError(path, "sensor_type is '" + type + "', not 'camera'");
  }
  const std::string model = YamlString(Required(root, "camera_model", path), "camera_model", path);
  if (model != "pinhole") {
    throw IoError(path, "camera_model '" + model + "' is not supported (only 'pinhole')");
  }
  const std::string distortion_model =
      YamlString(Required(root, "distortion_model", path), "distortion_model", path);
  if (distortion_model != "radial-tangential" && distortion_model != "radtan") {
    throw IoError(path, "distortion_model '" + distortion_model +
                            "' is not supported (only 'radial-tangential')");
  }
  const std::vector<double> k = YamlNumbers(Required(root, "intrinsics", path), "intrinsics", path);
  ExpectCount(k, 4, path, "'intrinsics' [fu, fv, cu, cv]");
  const std::vector<double> d =
      YamlNumbers(Required(root, "distortion_coefficients", path), "distortion_coefficients", path);
  if (d.size() != 4 && d.size() != 5) {
    throw IoError(path,
                  "'distortion_coefficients': expected 4 numbers [k1, k2, p1, p2] (or 5 "
                  "with k3), found " +
                      std::to_string(d.size()));
  }
  const std::vector<double> size =
      YamlNumbers(Required(root, "resolution", path), "resolution", path);
  ExpectCount(size, 2, path, "'resolution' [width, height]");

  EurocCamera result;
  sensor::Camera& camera = result.camera;
  if (!(k[0] > 0) || !(k[1] > 0)) {
    throw IoError(path,
                  "non-positive focal length (fu = " + Num(k[0]) + ", fv = " + Num(k[1]) + ")");
  }
  camera.K = PinholeIntrinsics{k[0], k[1], k[2], k[3]};
  camera.distortion.k1 = d[0];
  camera.distortion.k2 = d[1];
  camera.distortion.p1 = d[2];
  camera.distortion.p2 = d[3];
  if (d.size() == 5) camera.distortion.k3 = d[4];
  camera.width = ImageDimension(size[0], path, "resolution width");
  camera.height = ImageDimension(size[1], path, "resolution height");
  camera = CheckedCamera(camera, path);
  result.T_b_c = EurocTransform(root, path);
  if (root["rate_hz"].IsDefined()) {
    result.rate_hz = YamlNumber(root["rate_hz"], path, "'rate_hz'");
    if (!(result.rate_hz > 0)) throw IoError(path, "'rate_hz' is not > 0");
  }
  return result;
}

}  // namespace

EurocCamera ReadEurocCamera(const std::string& path) {
  const YAML::Node root = LoadYaml(path);
  try {
    return ParseEurocCamera(root, path);
  } catch (const YAML::Exception& e) {  // a node of an unexpected kind deep inside
    throw IoError(path, std::string("unexpected YAML structure: ") + e.what());
  }
}

}  // namespace io
}  // namespace plucker
