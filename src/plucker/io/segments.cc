#include "plucker/io/segments.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "plucker/io/kitti_lidar.h"  // ReadFileToString

namespace plucker {
namespace io {
namespace {

constexpr double kMaxCoordinate = 1e6;  // px; anything beyond is garbage, not an image

bool IsSeparator(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == ',' || c == '\v' || c == '\f';
}

std::vector<std::string> SplitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && IsSeparator(line[i])) ++i;
    std::size_t j = i;
    while (j < line.size() && !IsSeparator(line[j])) ++j;
    if (j > i) fields.push_back(line.substr(i, j - i));
    i = j;
  }
  return fields;
}

// Parses a whole field as a finite number; std::nullopt otherwise.
std::optional<double> ParseDouble(const std::string& field) {
  const char* begin = field.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (end == begin || *end != '\0' || !std::isfinite(v)) return std::nullopt;
  return v;
}

IoError LineError(const std::string& name, int line, const std::string& problem) {
  return IoError(name + ":" + std::to_string(line), problem);
}

// `# detection_ms <number>`: sets *ms; other comments are ignored.
void ParseComment(const std::string& line, const std::string& name, int number,
                  std::optional<double>* ms) {
  const std::vector<std::string> fields = SplitFields(line.substr(line.find('#') + 1));
  if (fields.empty() || fields[0] != "detection_ms") return;
  const std::optional<double> v = fields.size() == 2 ? ParseDouble(fields[1]) : std::nullopt;
  if (!v || *v < 0.0 || *v > 1e9) {
    throw LineError(name, number, "expected `# detection_ms <number in [0, 1e9]>`");
  }
  *ms = v;
}

}  // namespace

SegmentFile ParseSegments(const std::string& text, const std::string& name) {
  SegmentFile file;
  std::istringstream in(text);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::size_t first = line.find_first_not_of(" \t\r\v\f");
    if (first == std::string::npos) continue;
    if (line[first] == '#') {
      ParseComment(line, name, number, &file.detection_ms);
      continue;
    }
    const std::vector<std::string> fields = SplitFields(line);
    if (fields.size() != 4) {
      throw LineError(
          name, number,
          "expected 4 numbers `x1 y1 x2 y2`, got " + std::to_string(fields.size()) + " fields");
    }
    Eigen::Vector4d s;
    for (int k = 0; k < 4; ++k) {
      const std::optional<double> v = ParseDouble(fields[k]);
      if (!v) {
        throw LineError(
            name, number,
            "field " + std::to_string(k + 1) + " is not a finite number: '" + fields[k] + "'");
      }
      if (std::abs(*v) > kMaxCoordinate) {
        throw LineError(
            name, number,
            "field " + std::to_string(k + 1) + " (" + fields[k] + ") is beyond +-1e6 px");
      }
      s[k] = *v;
    }
    file.segments.push_back(s);
  }
  return file;
}

SegmentFile ReadSegments(const std::string& path) {
  return ParseSegments(ReadFileToString(path), path);
}

std::string FormatSegments(const SegmentFile& file, const std::vector<std::string>& header) {
  std::string out;
  for (const std::string& h : header) out += "# " + h + "\n";
  char buf[160];
  if (file.detection_ms) {
    std::snprintf(buf, sizeof(buf), "# detection_ms %.3f\n", *file.detection_ms);
    out += buf;
  }
  for (const Eigen::Vector4d& s : file.segments) {
    std::snprintf(buf, sizeof(buf), "%.3f %.3f %.3f %.3f\n", s[0], s[1], s[2], s[3]);
    out += buf;
  }
  return out;
}

void WriteSegments(const std::string& path, const SegmentFile& file,
                   const std::vector<std::string>& header) {
  WriteFileAtomically(path, FormatSegments(file, header));
}

}  // namespace io
}  // namespace plucker
