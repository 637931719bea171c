#include "plucker/io/euroc_imu.h"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "plucker/io/io_error.h"
#include "plucker/io/kitti_lidar.h"

namespace plucker {
namespace io {

namespace {

namespace fs = std::filesystem;

std::string Where(const std::string& name, int line) { return name + ":" + std::to_string(line); }

// The comma-separated fields of one row (surrounding blanks allowed).
std::vector<std::string> SplitFields(const std::string& row) {
  std::vector<std::string> fields;
  std::stringstream s(row);
  std::string f;
  while (std::getline(s, f, ',')) fields.push_back(f);
  return fields;
}

double ParseFinite(const std::string& field, const std::string& where) {
  char* end = nullptr;
  const double v = std::strtod(field.c_str(), &end);
  while (end && (*end == ' ' || *end == '\r')) ++end;
  if (end == field.c_str() || *end != '\0' || !std::isfinite(v)) {
    throw IoError(where, "bad number '" + field + "'");
  }
  return v;
}

// Calls row(fields, where, t) for every data row (comments '#' and blank lines skipped) with
// `columns` fields and increasing timestamps; t in seconds since origin_ns.
template <typename Row>
void ForEachRow(const std::string& text, const std::string& name, std::size_t columns,
                std::int64_t origin_ns, Row row) {
  std::stringstream in(text);
  std::string line;
  int line_no = 0;
  std::int64_t last_ns = -1;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const std::string where = Where(name, line_no);
    const std::vector<std::string> fields = SplitFields(line);
    if (fields.size() != columns) {
      throw IoError(where,
                    std::to_string(fields.size()) + " fields, expected " + std::to_string(columns));
    }
    const std::int64_t ns = ParseEurocNanoseconds(fields[0], where);
    if (ns <= last_ns) throw IoError(where, "timestamp does not increase");
    last_ns = ns;
    std::vector<double> v(columns - 1);
    for (std::size_t k = 1; k < columns; ++k) v[k - 1] = ParseFinite(fields[k], where);
    row(v, where, static_cast<double>(ns - origin_ns) * 1e-9);
  }
  if (last_ns < 0) throw IoError(name, "empty file: no data rows");
}

std::int64_t FirstTimestamp(const std::string& text, const std::string& name) {
  std::int64_t first = -1;
  std::stringstream in(text);
  std::string line;
  int line_no = 0;
  while (first < 0 && std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#' || line == "\r") continue;
    first = ParseEurocNanoseconds(SplitFields(line)[0], Where(name, line_no));
  }
  if (first < 0) throw IoError(name, "empty file: no data rows");
  return first;
}

double PositiveKey(const YAML::Node& root, const char* key, const std::string& name) {
  const YAML::Node n = root[key];
  if (!n) throw IoError(name, std::string("missing key '") + key + "'");
  double v = 0.0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    throw IoError(name, std::string("key '") + key + "' is not a number");
  }
  if (!std::isfinite(v) || v <= 0.0) {
    throw IoError(name, std::string("key '") + key + "' must be positive and finite");
  }
  return v;
}

void CheckIdentityTbs(const YAML::Node& root, const std::string& name) {
  const YAML::Node t_bs = root["T_BS"];
  if (!t_bs) return;  // absent: the body frame is the IMU frame
  // A scalar or a list has no "data" (yaml-cpp would throw BadSubscript, not an IoError).
  if (!t_bs.IsMap()) throw IoError(name, "T_BS must be a map with rows, cols and data");
  const YAML::Node data = t_bs["data"];
  if (!data.IsSequence() || data.size() != 16) {
    throw IoError(name, "T_BS/data must hold 16 numbers");
  }
  for (int k = 0; k < 16; ++k) {
    double v = 0.0;
    try {
      v = data[k].as<double>();
    } catch (const YAML::Exception&) {
      throw IoError(name, "T_BS/data holds a non-number");
    }
    if (std::abs(v - (k % 5 == 0 ? 1.0 : 0.0)) > 1e-9) {
      throw IoError(name, "T_BS is not the identity (the IMU must define the body frame)");
    }
  }
}

}  // namespace

std::int64_t ParseEurocNanoseconds(const std::string& field, const std::string& where) {
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(field.c_str(), &end, 10);
  while (end && (*end == ' ' || *end == '\r')) ++end;
  if (end == field.c_str() || *end != '\0' || errno == ERANGE || v < 0) {
    throw IoError(where, "bad timestamp '" + field + "' (need integer nanoseconds)");
  }
  return v;
}

std::vector<sensor::ImuSample> ParseEurocImuCsv(const std::string& text, const std::string& name,
                                                std::int64_t origin_ns) {
  std::vector<sensor::ImuSample> samples;
  ForEachRow(text, name, 7, origin_ns,
             [&](const std::vector<double>& v, const std::string&, double t) {
               sensor::ImuSample s;
               s.t = t;
               s.gyro = Eigen::Vector3d(v[0], v[1], v[2]);
               s.accel = Eigen::Vector3d(v[3], v[4], v[5]);
               samples.push_back(s);
             });
  return samples;
}

std::vector<sensor::BodyState> ParseEurocGroundTruthCsv(const std::string& text,
                                                        const std::string& name,
                                                        std::int64_t origin_ns) {
  std::vector<sensor::BodyState> states;
  ForEachRow(text, name, 17, origin_ns,
             [&](const std::vector<double>& v, const std::string& where, double t) {
               const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);  // w, x, y, z in the file
               const double n2 = q.squaredNorm();
               if (!(n2 > 1e-12) || !std::isfinite(n2)) {
                 throw IoError(where, "zero or overflowing quaternion");
               }
               sensor::BodyState s;
               s.t = t;
               s.T_w_b = SE3d(q, Eigen::Vector3d(v[0], v[1], v[2]));
               s.v_w = Eigen::Vector3d(v[7], v[8], v[9]);
               s.bias.gyro = Eigen::Vector3d(v[10], v[11], v[12]);
               s.bias.accel = Eigen::Vector3d(v[13], v[14], v[15]);
               states.push_back(s);
             });
  return states;
}

sensor::ImuModel ParseEurocImuYaml(const std::string& text, const std::string& name) {
  // EuRoC files start with OpenCV's "%YAML:1.0", which is not a YAML directive: drop it.
  std::string body = text;
  if (body.rfind("%YAML", 0) == 0) body.erase(0, body.find('\n'));
  YAML::Node root;
  try {
    root = YAML::Load(body);
  } catch (const YAML::Exception& e) {
    throw IoError(name, std::string("not YAML: ") + e.what());
  }
  if (!root.IsMap()) throw IoError(name, "not a YAML map of sensor settings");
  CheckIdentityTbs(root, name);
  sensor::ImuModel m;
  m.rate_hz = PositiveKey(root, "rate_hz", name);
  m.gyro_noise_density = PositiveKey(root, "gyroscope_noise_density", name);
  m.gyro_bias_random_walk = PositiveKey(root, "gyroscope_random_walk", name);
  m.accel_noise_density = PositiveKey(root, "accelerometer_noise_density", name);
  m.accel_bias_random_walk = PositiveKey(root, "accelerometer_random_walk", name);
  return m;
}

EurocGroundTruth ReadEurocGroundTruthCsv(const std::string& path) {
  EurocGroundTruth g;
  const std::string text = ReadFileToString(path);
  g.origin_ns = FirstTimestamp(text, path);
  g.states = ParseEurocGroundTruthCsv(text, path, g.origin_ns);
  return g;
}

EurocImuRecording ReadEurocImuRecording(const std::string& dir) {
  fs::path mav0 = fs::path(dir) / "mav0";
  if (!fs::is_directory(mav0)) mav0 = fs::path(dir);
  const fs::path imu_csv = mav0 / "imu0" / "data.csv";
  const fs::path imu_yaml = mav0 / "imu0" / "sensor.yaml";
  const fs::path gt_csv = mav0 / "state_groundtruth_estimate0" / "data.csv";
  if (!fs::is_regular_file(imu_csv)) {
    throw IoError(dir, "not a EuRoC folder: no mav0/imu0/data.csv");
  }
  EurocImuRecording r;
  const std::string imu_text = ReadFileToString(imu_csv.string());
  r.origin_ns = FirstTimestamp(imu_text, imu_csv.string());
  r.imu = ParseEurocImuCsv(imu_text, imu_csv.string(), r.origin_ns);
  r.imu_model = ParseEurocImuYaml(ReadFileToString(imu_yaml.string()), imu_yaml.string());
  if (fs::is_regular_file(gt_csv)) {
    r.ground_truth =
        ParseEurocGroundTruthCsv(ReadFileToString(gt_csv.string()), gt_csv.string(), r.origin_ns);
  }
  return r;
}

}  // namespace io
}  // namespace plucker
