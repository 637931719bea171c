#include "plucker/io/kitti_lidar.h"

#include <Eigen/SVD>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace plucker {
namespace io {
namespace {

constexpr std::size_t kRecordBytes = 16;

float LoadFloatLE(const char* p) {
  std::uint32_t u = static_cast<std::uint32_t>(static_cast<unsigned char>(p[0])) |
                    static_cast<std::uint32_t>(static_cast<unsigned char>(p[1])) << 8 |
                    static_cast<std::uint32_t>(static_cast<unsigned char>(p[2])) << 16 |
                    static_cast<std::uint32_t>(static_cast<unsigned char>(p[3])) << 24;
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

void StoreFloatLE(float f, std::string* out) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  for (int i = 0; i < 4; ++i) out->push_back(static_cast<char>((u >> (8 * i)) & 0xFF));
}

// Parses a whole-token double; false on junk, empty or out-of-range text.
bool ParseDouble(const std::string& token, double* value) {
  if (token.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  if (end != token.c_str() + token.size() || errno == ERANGE) return false;
  *value = v;
  return true;
}

std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

}  // namespace

std::string ReadFileToString(const std::string& path) {
  std::string bytes;
  ReadFileInto(path, &bytes);
  return bytes;
}

void ReadFileInto(const std::string& path, std::string* bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, std::string("cannot open: ") + std::strerror(errno));
  in.seekg(0, std::ios::end);
  const std::streamoff size = in ? static_cast<std::streamoff>(in.tellg()) : -1;
  in.clear();
  in.seekg(0);
  in.clear();      // a pipe cannot seek: then its size is unknown (read in chunks below)
  if (size > 0) {  // regular file: one read of the known size (a reused buffer is not cleared
                   // first: resize then zeroes only what exceeds the previous file's size)
    bytes->resize(static_cast<std::size_t>(size));
    in.read(&(*bytes)[0], size);
    bytes->resize(static_cast<std::size_t>(in.gcount()));
    if (in.bad()) throw IoError(path, "read failed");
    if (in.peek() == std::ifstream::traits_type::eof()) return;
    in.clear();
  } else {
    bytes->clear();
  }
  // Unknown size, or a file that grew meanwhile: read the rest in chunks.
  char chunk[65536];
  while (in.read(chunk, sizeof(chunk)) || in.gcount() > 0)
    bytes->append(chunk, static_cast<std::size_t>(in.gcount()));
  if (in.bad()) throw IoError(path, "read failed");
}

LidarScan ParseKittiBin(const std::string& bytes, const std::string& name, ScanReadStats* stats) {
  LidarScan scan;
  ParseKittiBin(bytes, name, &scan, stats);
  return scan;
}

void ParseKittiBin(const std::string& bytes, const std::string& name, LidarScan* scan,
                   ScanReadStats* stats) {
  if (bytes.empty()) throw IoError(name, "empty scan (0 bytes)");
  if (bytes.size() % kRecordBytes != 0) {
    throw IoError(name, "truncated: size " + std::to_string(bytes.size()) +
                            " bytes is not a multiple of 16 (float32 x y z intensity records)");
  }
  const std::size_t n = bytes.size() / kRecordBytes;
  scan->points.resize(n);  // filled below, then cut to the finite records
  scan->intensity.resize(n);
  scan->ring.clear();
  scan->time.clear();
  scan->timestamp = 0.0;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const char* rec = bytes.data() + i * kRecordBytes;
    const float x = LoadFloatLE(rec), y = LoadFloatLE(rec + 4), z = LoadFloatLE(rec + 8);
    const float intensity = LoadFloatLE(rec + 12);
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) continue;
    scan->points[kept] = Eigen::Vector3d(x, y, z);
    scan->intensity[kept] = std::isfinite(intensity) ? intensity : 0.0f;
    ++kept;
  }
  scan->points.resize(kept);
  scan->intensity.resize(kept);
  if (stats) {
    stats->points_in_file = n;
    stats->non_finite_dropped = n - kept;
  }
  if (kept == 0) {
    throw IoError(name, "no finite point (" + std::to_string(n) + " records, all NaN/Inf)");
  }
}

LidarScan ReadKittiBin(const std::string& path, ScanReadStats* stats) {
  return ParseKittiBin(ReadFileToString(path), path, stats);
}

std::string SerializeKittiBin(const LidarScan& scan) {
  std::string out;
  out.reserve(scan.size() * kRecordBytes);
  const bool has_i = scan.intensity.size() == scan.size();
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const Eigen::Vector3d& p = scan.points[i];
    StoreFloatLE(static_cast<float>(p.x()), &out);
    StoreFloatLE(static_cast<float>(p.y()), &out);
    StoreFloatLE(static_cast<float>(p.z()), &out);
    StoreFloatLE(has_i ? scan.intensity[i] : 0.0f, &out);
  }
  return out;
}

void WriteKittiBin(const std::string& path, const LidarScan& scan) {
  WriteFileAtomically(path, SerializeKittiBin(scan));
}

std::optional<SE3d> ParseKittiCalibTr(const std::string& text, const std::string& name) {
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = Trim(line);
    if (t.rfind("Tr:", 0) != 0 && t.rfind("Tr_velo_cam:", 0) != 0 &&
        t.rfind("Tr_velo_to_cam:", 0) != 0) {
      continue;
    }
    const std::string where = "line " + std::to_string(line_no) + ": Tr: ";
    std::istringstream fields(t.substr(t.find(':') + 1));
    std::vector<double> v;
    std::string token;
    while (fields >> token) {
      double d;
      if (!ParseDouble(token, &d)) throw IoError(name, where + "malformed number '" + token + "'");
      if (!std::isfinite(d)) throw IoError(name, where + "non-finite number '" + token + "'");
      v.push_back(d);
    }
    if (v.size() != 12) {
      throw IoError(name, where + "expected 12 numbers, got " + std::to_string(v.size()));
    }
    Eigen::Matrix3d R;
    Eigen::Vector3d tr;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) R(r, c) = v[4 * r + c];
      tr(r) = v[4 * r + 3];
    }
    const double err = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (err > 1e-2 || R.determinant() <= 0.0) {
      throw IoError(
          name, where + "3x3 block is not a rotation (max |R^T R - I| = " + std::to_string(err) +
                    ", det = " + std::to_string(R.determinant()) + ")");
    }
    // Nearest rotation (polar decomposition via SVD).
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d Rn = svd.matrixU() * svd.matrixV().transpose();
    if (Rn.determinant() < 0) {
      Eigen::Matrix3d U = svd.matrixU();
      U.col(2) *= -1.0;
      Rn = U * svd.matrixV().transpose();
    }
    return SE3d(Rn, tr);
  }
  return std::nullopt;
}

std::optional<SE3d> ReadKittiCalibTr(const std::string& path) {
  return ParseKittiCalibTr(ReadFileToString(path), path);
}

void WriteKittiCalibTr(const std::string& path, const SE3d& T_cam0_velo) {
  const Eigen::Matrix4d m = T_cam0_velo.Matrix();
  std::string out = "Tr:";
  char buf[64];
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      std::snprintf(buf, sizeof(buf), " %.17g", m(r, c));
      out += buf;
    }
  }
  out += "\n";
  WriteFileAtomically(path, out);
}

std::vector<double> ParseKittiTimes(const std::string& text, const std::string& name) {
  std::vector<double> times;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = Trim(line);
    if (t.empty()) continue;
    const std::string where = "line " + std::to_string(line_no) + ": ";
    double v;
    if (!ParseDouble(t, &v)) throw IoError(name, where + "not a number: '" + t.substr(0, 40) + "'");
    if (!std::isfinite(v)) throw IoError(name, where + "non-finite time '" + t + "'");
    if (!times.empty() && v < times.back()) {
      throw IoError(
          name, where + "time decreases (" + t + " after " + std::to_string(times.back()) + ")");
    }
    times.push_back(v);
  }
  return times;
}

std::vector<double> ReadKittiTimes(const std::string& path) {
  return ParseKittiTimes(ReadFileToString(path), path);
}

void WriteKittiTimes(const std::string& path, const std::vector<double>& times) {
  std::string out;
  char buf[64];
  for (double t : times) {
    std::snprintf(buf, sizeof(buf), "%.9e\n", t);
    out += buf;
  }
  WriteFileAtomically(path, out);
}

}  // namespace io
}  // namespace plucker
