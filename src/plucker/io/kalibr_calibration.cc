#include "plucker/io/kalibr_calibration.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdlib>

#include "plucker/io/calibration_yaml_internal.h"

namespace plucker {
namespace io {
namespace {

using namespace internal;  // NOLINT(build/namespaces): the shared field readers

constexpr double kMaxRigidError = 1e-6;  // max |R^T R - I| of a Kalibr 4x4

// A 4x4 rigid transform: 4 rows of 4 numbers (Kalibr) or 16 numbers row-major.
SE3d RigidTransform(const YAML::Node& node, const std::string& key, const std::string& path) {
  std::vector<double> v;
  if (node.IsSequence() && node.size() == 4 && node[0].IsSequence()) {
    for (std::size_t r = 0; r < 4; ++r) {
      const std::vector<double> row =
          YamlNumbers(node[r], key + " row " + std::to_string(r + 1), path);
      ExpectCount(row, 4, path, "'" + key + "' row " + std::to_string(r + 1));
      v.insert(v.end(), row.begin(), row.end());
    }
  } else {
    v = YamlNumbers(node, key, path);
    ExpectCount(v, 16, path, "'" + key + "' (a 4x4 matrix)");
  }
  if (v[12] != 0 || v[13] != 0 || v[14] != 0 || v[15] != 1) {
    throw IoError(path, "'" + key + "' is not a rigid transform: last row is not (0, 0, 0, 1)");
  }
  Eigen::Matrix3d R;
  R << v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10];
  return SE3d(CheckedRotation(R, path, "'" + key + "' rotation", kMaxRigidError),
              Eigen::Vector3d(v[3], v[7], v[11]));
}

std::optional<YAML::Node> Optional(const YAML::Node& node, const std::string& key) {
  const YAML::Node child = node[key];
  if (!child.IsDefined() || child.IsNull()) return std::nullopt;
  return child;
}

YAML::Node Field(const YAML::Node& cam, const std::string& name, const std::string& key,
                 const std::string& path) {
  const auto child = Optional(cam, key);
  if (!child) throw IoError(path, "missing key '" + name + "." + key + "'");
  return *child;
}

sensor::Camera ParseCamera(const YAML::Node& cam, const std::string& name,
                           const std::string& path) {
  const std::string camera_model =
      YamlString(Field(cam, name, "camera_model", path), name + ".camera_model", path);
  const std::string distortion_model =
      YamlString(Field(cam, name, "distortion_model", path), name + ".distortion_model", path);
  if (camera_model != "pinhole" ||
      (distortion_model != "radtan" && distortion_model != "equidistant")) {
    throw IoError(path, name + ": camera_model '" + camera_model + "' with distortion_model '" +
                            distortion_model +
                            "' is not supported (only pinhole with radtan or equidistant)");
  }
  const std::vector<double> k =
      YamlNumbers(Field(cam, name, "intrinsics", path), name + ".intrinsics", path);
  ExpectCount(k, 4, path, "'" + name + ".intrinsics' [fu, fv, pu, pv]");
  const std::vector<double> d =
      YamlNumbers(Field(cam, name, "distortion_coeffs", path), name + ".distortion_coeffs", path);
  ExpectCount(d, 4, path,
              "'" + name + ".distortion_coeffs' " +
                  (distortion_model == "radtan" ? "[k1, k2, p1, p2]" : "[k1, k2, k3, k4]"));
  const std::vector<double> size =
      YamlNumbers(Field(cam, name, "resolution", path), name + ".resolution", path);
  ExpectCount(size, 2, path, "'" + name + ".resolution' [width, height]");
  sensor::Camera camera;
  camera.K = PinholeIntrinsics{k[0], k[1], k[2], k[3]};
  if (distortion_model == "radtan") {
    camera.distortion.k1 = d[0];
    camera.distortion.k2 = d[1];
    camera.distortion.p1 = d[2];
    camera.distortion.p2 = d[3];
  } else {
    camera.model = sensor::CameraModel::kEquidistant;
    camera.equidistant = EquidistantDistortion{d[0], d[1], d[2], d[3]};
  }
  camera.width = ImageDimension(size[0], path, name + ".resolution width");
  camera.height = ImageDimension(size[1], path, name + ".resolution height");
  const std::string problem = camera.Problem();
  if (!problem.empty()) throw IoError(path, name + ": " + problem);
  return camera;
}

KalibrCamera ParseChainCamera(const YAML::Node& cam, const std::string& name,
                              const std::string& path) {
  if (!cam.IsMap()) throw IoError(path, "'" + name + "' is not a map of camera keys");
  KalibrCamera result;
  result.name = name;
  result.camera = ParseCamera(cam, name, path);
  const auto cam_imu = Optional(cam, "T_cam_imu");
  const auto imu_cam = Optional(cam, "T_imu_cam");
  if (cam_imu && imu_cam) {
    throw IoError(path, name + " has both T_cam_imu and T_imu_cam (one IMU extrinsic expected)");
  }
  if (cam_imu) result.T_b_c = RigidTransform(*cam_imu, name + ".T_cam_imu", path).Inverse();
  if (imu_cam) result.T_b_c = RigidTransform(*imu_cam, name + ".T_imu_cam", path);
  if (const auto t = Optional(cam, "T_cn_cnm1")) {
    result.T_cn_cnm1 = RigidTransform(*t, name + ".T_cn_cnm1", path);
  }
  if (const auto shift = Optional(cam, "timeshift_cam_imu")) {
    result.timeshift_cam_imu = YamlNumber(*shift, path, "'" + name + ".timeshift_cam_imu'");
  }
  return result;
}

// The camera index of a top-level key "camN" (N decimal, no sign or leading zero), or -1.
int CameraIndex(const std::string& key) {
  if (key.size() < 4 || key.size() > 6 || key.compare(0, 3, "cam") != 0) return -1;
  if (key.size() > 4 && key[3] == '0') return -1;
  int n = 0;
  for (std::size_t i = 3; i < key.size(); ++i) {
    if (key[i] < '0' || key[i] > '9') return -1;
    n = 10 * n + (key[i] - '0');
  }
  return n;
}

KalibrCameraChain ParseChain(const YAML::Node& root, const std::string& path) {
  std::vector<std::pair<int, std::string>> keys;
  for (const auto& entry : root) {
    if (!entry.first.IsScalar()) continue;
    const int index = CameraIndex(entry.first.Scalar());
    if (index >= 0) keys.emplace_back(index, entry.first.Scalar());
  }
  if (keys.empty()) throw IoError(path, "no camera (a camchain has keys cam0, cam1, ...)");
  std::sort(keys.begin(), keys.end());
  KalibrCameraChain chain;
  chain.path = path;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (keys[i].first != static_cast<int>(i)) {
      throw IoError(path, "cameras are not numbered from cam0 without gaps: '" + keys[i].second +
                              "' follows " + (i == 0 ? "nothing" : "'" + keys[i - 1].second + "'"));
    }
    chain.cameras.push_back(ParseChainCamera(root[keys[i].second], keys[i].second, path));
  }
  return chain;
}

double PositiveField(const YAML::Node& node, const std::string& key, const std::string& path) {
  const double v = YamlNumber(Required(node, key, path), path, "'" + key + "'");
  if (!(v > 0)) throw IoError(path, "'" + key + "' = " + Num(v) + " is not > 0");
  return v;
}

}  // namespace

SE3d KalibrCameraChain::RequireT_b_c(std::size_t index) const {
  if (index >= cameras.size()) {
    throw IoError(path, "no camera cam" + std::to_string(index) + " (the chain has " +
                            std::to_string(cameras.size()) + ")");
  }
  if (!cameras[index].T_b_c) {
    throw IoError(path, "missing key '" + cameras[index].name +
                            ".T_cam_imu' (the IMU extrinsic; calibrate with kalibr_calibrate_imu_"
                            "camera, or give OpenVINS' T_imu_cam)");
  }
  return *cameras[index].T_b_c;
}

KalibrCameraChain ParseKalibrCameraChain(const std::string& text, const std::string& path) {
  const YAML::Node root = ParseYamlMap(text, path);
  try {
    return ParseChain(root, path);
  } catch (const YAML::Exception& e) {  // a node of an unexpected kind deep inside
    throw IoError(path, std::string("unexpected YAML structure: ") + e.what());
  }
}

KalibrCameraChain ReadKalibrCameraChain(const std::string& path) {
  return ParseKalibrCameraChain(ReadText(path), path);
}

sensor::ImuModel ParseKalibrImu(const std::string& text, const std::string& path) {
  YAML::Node root = ParseYamlMap(text, path);
  try {
    if (const auto imu0 = Optional(root, "imu0")) {  // OpenVINS' kalibr_imu_chain.yaml
      if (!imu0->IsMap()) throw IoError(path, "'imu0' is not a map of IMU keys");
      root = *imu0;
    }
    sensor::ImuModel m;
    m.accel_noise_density = PositiveField(root, "accelerometer_noise_density", path);
    m.accel_bias_random_walk = PositiveField(root, "accelerometer_random_walk", path);
    m.gyro_noise_density = PositiveField(root, "gyroscope_noise_density", path);
    m.gyro_bias_random_walk = PositiveField(root, "gyroscope_random_walk", path);
    m.rate_hz = PositiveField(root, "update_rate", path);
    return m;
  } catch (const YAML::Exception& e) {
    throw IoError(path, std::string("unexpected YAML structure: ") + e.what());
  }
}

sensor::ImuModel ReadKalibrImu(const std::string& path) {
  return ParseKalibrImu(ReadText(path), path);
}

}  // namespace io
}  // namespace plucker
