#include "plucker/io/trajectory_io.h"

#include <algorithm>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <Eigen/SVD>

namespace plucker {
namespace io {
namespace {

// Tolerances for "almost a rotation": beyond them the input is rejected, within them repaired.
constexpr double kMaxOrthonormalityError = 1e-3;  // max |R^T R - I| of a KITTI 3x3 block
constexpr double kMaxQuaternionNormError = 1e-3;  // | |q| - 1 | of a TUM quaternion
constexpr double kMinQuaternionNorm = 1e-12;

std::string Num(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

// Splits a data line into fields (whitespace or commas separate). Returns false for a blank
// line or a '#' comment.
bool SplitFields(const std::string& line, std::vector<std::string>* fields) {
  fields->clear();
  std::size_t i = 0;
  const std::size_t n = line.size();
  auto is_sep = [](char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == ',' || c == '\v' || c == '\f';
  };
  while (i < n && is_sep(line[i])) ++i;
  if (i == n || line[i] == '#') return false;
  while (i < n) {
    std::size_t j = i;
    while (j < n && !is_sep(line[j])) ++j;
    fields->push_back(line.substr(i, j - i));
    while (j < n && is_sep(line[j])) ++j;
    i = j;
  }
  return true;
}

double ParseNumber(const std::string& field, const std::string& name, int line, int index) {
  const char* begin = field.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (end == begin || *end != '\0') {
    throw TrajectoryParseError(
        name, line, "field " + std::to_string(index + 1) + " is not a number: '" + field + "'");
  }
  if (!std::isfinite(v)) {
    throw TrajectoryParseError(
        name, line, "field " + std::to_string(index + 1) + " is not finite: '" + field + "'");
  }
  return v;
}

SE3d KittiPose(const std::vector<double>& v, const std::string& name, int line) {
  Eigen::Matrix3d R;
  R << v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10];
  const Eigen::Vector3d t(v[3], v[7], v[11]);
  const double det = R.determinant();
  const double ortho_error =
      (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(det > 0.0) || ortho_error > kMaxOrthonormalityError) {
    throw TrajectoryParseError(name, line,
                               "the 3x3 block is not a rotation (max |R^T R - I| = " +
                                   Num(ortho_error) + ", det = " + Num(det) + ")");
  }
  // Re-orthonormalise the small rounding errors of text files: the nearest rotation U V^T.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d R_clean = svd.matrixU() * svd.matrixV().transpose();
  return SE3d(R_clean, t);
}

SE3d TumPose(const std::vector<double>& v, const std::string& name, int line) {
  const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);  // Eigen's constructor takes w first
  const double norm = q.norm();
  if (norm < kMinQuaternionNorm) {
    throw TrajectoryParseError(name, line, "zero quaternion");
  }
  if (std::abs(norm - 1.0) > kMaxQuaternionNormError) {
    throw TrajectoryParseError(
        name, line,
        "quaternion norm " + Num(norm) + " is not 1 (expected `t tx ty tz qx qy qz qw`)");
  }
  return SE3d(q.normalized(), Eigen::Vector3d(v[1], v[2], v[3]));
}

std::string FormatDouble(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v);  // shortest exact representation
  return std::string(buf, r.ptr);
}

std::string KittiLine(const SE3d& T) {
  const Eigen::Matrix<double, 4, 4> m = T.Matrix();
  std::string s;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      if (r + c > 0) s += ' ';
      s += FormatDouble(m(r, c));
    }
  }
  s += '\n';
  return s;
}

std::string ReadWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, std::string("cannot open: ") + std::strerror(errno));
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) throw IoError(path, "read failed");
  return s.str();
}

}  // namespace

Trajectory ParseTrajectory(const std::string& text, const std::string& name,
                           TrajectoryFormat format) {
  Trajectory traj;
  std::istringstream in(text);
  std::string line;
  std::vector<std::string> fields;
  std::vector<double> values;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!SplitFields(line, &fields)) continue;
    const int n = static_cast<int>(fields.size());
    if (format == TrajectoryFormat::kAuto) {
      if (n == 12) {
        format = TrajectoryFormat::kKitti;
      } else if (n == 8) {
        format = TrajectoryFormat::kTum;
      } else {
        throw TrajectoryParseError(name, line_no,
                                   "cannot detect the format: " + std::to_string(n) +
                                       " fields (KITTI has 12, TUM `t tx ty tz qx qy qz qw` 8)");
      }
    }
    const int expected = format == TrajectoryFormat::kKitti ? 12 : 8;
    if (n != expected) {
      throw TrajectoryParseError(name, line_no,
                                 std::to_string(n) + " fields, expected " +
                                     std::to_string(expected) + " (" + FormatName(format) + ")");
    }
    values.resize(n);
    for (int i = 0; i < n; ++i) values[i] = ParseNumber(fields[i], name, line_no, i);
    if (format == TrajectoryFormat::kKitti) {
      traj.poses.push_back(KittiPose(values, name, line_no));
    } else {
      if (!traj.times.empty() && values[0] < traj.times.back()) {
        throw TrajectoryParseError(name, line_no,
                                   "timestamp " + FormatDouble(values[0]) +
                                       " is before the previous one " +
                                       FormatDouble(traj.times.back()));
      }
      traj.times.push_back(values[0]);
      traj.poses.push_back(TumPose(values, name, line_no));
    }
  }
  if (traj.poses.empty()) throw IoError(name, "empty file: no poses");
  return traj;
}

Trajectory ReadTrajectory(const std::string& path, TrajectoryFormat format) {
  return ParseTrajectory(ReadWholeFile(path), path, format);
}

void WriteKittiPoses(const std::string& path, const std::vector<SE3d>& poses) {
  std::string out;
  out.reserve(poses.size() * 12 * 12);
  for (const SE3d& T : poses) out += KittiLine(T);
  WriteFileAtomically(path, out);
}

void WriteTumTrajectory(const std::string& path, const std::vector<double>& times,
                        const std::vector<SE3d>& poses, const std::vector<std::string>& comments) {
  if (times.size() != poses.size()) {
    throw IoError(path, "cannot write a TUM trajectory with " + std::to_string(times.size()) +
                            " times and " + std::to_string(poses.size()) + " poses");
  }
  std::string out = "# t tx ty tz qx qy qz qw\n";
  for (const std::string& c : comments) out += "# " + c + "\n";
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Eigen::Vector3d& t = poses[i].translation();
    const Eigen::Quaterniond& q = poses[i].rotation();
    const double v[8] = {times[i], t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
    for (int k = 0; k < 8; ++k) {
      if (k > 0) out += ' ';
      out += FormatDouble(v[k]);
    }
    out += '\n';
  }
  WriteFileAtomically(path, out);
}

std::string FormatNanosecondsAsSeconds(std::int64_t ns) {
  const bool negative = ns < 0;
  // The magnitude as unsigned, so that INT64_MIN has one too.
  const std::uint64_t m = negative ? 0 - static_cast<std::uint64_t>(ns) : ns;
  std::string frac = std::to_string(m % 1000000000ULL);
  frac.insert(0, 9 - frac.size(), '0');
  return (negative ? "-" : "") + std::to_string(m / 1000000000ULL) + "." + frac;
}

void WriteTumTrajectoryOnClock(const std::string& path, std::int64_t origin_ns,
                               const std::vector<double>& times, const std::vector<SE3d>& poses,
                               const std::vector<std::string>& header) {
  if (times.size() != poses.size()) {
    throw IoError(path, "cannot write a TUM trajectory with " + std::to_string(times.size()) +
                            " times and " + std::to_string(poses.size()) + " poses");
  }
  std::string out;
  for (const std::string& line : header) out += "# " + line + "\n";
  out += "# stamps: seconds on the recording's own clock\n# t tx ty tz qx qy qz qw\n";
  for (std::size_t i = 0; i < poses.size(); ++i) {
    // |t| below 2^62 ns (146 years) keeps the sum in range.
    if (!std::isfinite(times[i]) || std::abs(times[i]) > 4.6e9) {
      throw IoError(path, "cannot write time " + FormatDouble(times[i]) + " on the clock");
    }
    out += FormatNanosecondsAsSeconds(origin_ns + std::llround(times[i] * 1e9));
    const Eigen::Vector3d& t = poses[i].translation();
    const Eigen::Quaterniond& q = poses[i].rotation();
    const double v[7] = {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
    for (int k = 0; k < 7; ++k) out += ' ' + FormatDouble(v[k]);
    out += '\n';
  }
  WriteFileAtomically(path, out);
}

std::vector<double> ReadTimes(const std::string& path) {
  const std::string text = ReadWholeFile(path);
  std::istringstream in(text);
  std::string line;
  std::vector<std::string> fields;
  std::vector<double> times;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!SplitFields(line, &fields)) continue;
    if (fields.size() != 1) {
      throw TrajectoryParseError(path, line_no,
                                 std::to_string(fields.size()) + " fields, expected 1 (a time)");
    }
    const double t = ParseNumber(fields[0], path, line_no, 0);
    if (!times.empty() && t < times.back()) {
      throw TrajectoryParseError(
          path, line_no,
          "time " + FormatDouble(t) + " is before the previous one " + FormatDouble(times.back()));
    }
    times.push_back(t);
  }
  if (times.empty()) throw IoError(path, "empty file: no times");
  return times;
}

std::string FormatName(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kAuto:
      return "auto";
    case TrajectoryFormat::kKitti:
      return "kitti";
    case TrajectoryFormat::kTum:
      return "tum";
  }
  return "unknown";
}

TrajectoryFormat ParseTrajectoryFormat(const std::string& name) {
  if (name == "auto") return TrajectoryFormat::kAuto;
  if (name == "kitti") return TrajectoryFormat::kKitti;
  if (name == "tum") return TrajectoryFormat::kTum;
  throw std::invalid_argument("unknown trajectory format '" + name +
                              "' (expected auto, kitti or tum)");
}

std::vector<std::optional<SE3d>> ReadKittiPosesWithGaps(const std::string& path) {
  const std::string text = ReadWholeFile(path);
  std::vector<std::optional<SE3d>> poses;
  std::istringstream in(text);
  std::string line;
  std::vector<std::string> fields;
  std::vector<double> values(12);
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!SplitFields(line, &fields)) continue;
    if (fields.size() != 12) {
      throw TrajectoryParseError(path, line_no,
                                 std::to_string(fields.size()) + " fields, expected 12 (kitti)");
    }
    const bool gap = std::all_of(fields.begin(), fields.end(), [](const std::string& f) {
      return f == "nan" || f == "NaN" || f == "NAN" || f == "-nan";
    });
    if (gap) {
      poses.emplace_back(std::nullopt);
      continue;
    }
    for (int i = 0; i < 12; ++i) values[i] = ParseNumber(fields[i], path, line_no, i);
    poses.emplace_back(KittiPose(values, path, line_no));
  }
  if (poses.empty()) throw IoError(path, "empty file: no poses");
  return poses;
}

void WriteKittiPosesWithGaps(const std::string& path,
                             const std::vector<std::optional<SE3d>>& poses) {
  std::string out;
  for (const auto& T : poses) {
    if (T) {
      out += KittiLine(*T);
    } else {
      out += "nan nan nan nan nan nan nan nan nan nan nan nan\n";
    }
  }
  WriteFileAtomically(path, out);
}

}  // namespace io
}  // namespace plucker
