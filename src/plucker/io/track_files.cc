#include "plucker/io/track_files.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace plucker {
namespace io {
namespace {

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, "cannot open the file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Calls row(values) for every data line with exactly `fields` finite numbers.
template <typename Row>
void ParseRows(const std::string& text, const std::string& name, int fields, const Row& row) {
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const std::string where = name + ":" + std::to_string(number);
    std::istringstream ls(line);
    std::vector<double> v;
    std::string token;
    while (ls >> token) {
      char* end = nullptr;
      const double x = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0') {
        throw IoError(where, "'" + token + "' is not a number");
      }
      if (!std::isfinite(x)) throw IoError(where, "non-finite value '" + token + "'");
      v.push_back(x);
    }
    if (static_cast<int>(v.size()) != fields) {
      throw IoError(
          where, "expected " + std::to_string(fields) + " fields, got " + std::to_string(v.size()));
    }
    if (v[0] != std::floor(v[0]) || v[0] < 0 || v[0] > 1e9) {
      throw IoError(where, "the frame must be an integer >= 0");
    }
    if (v[1] != std::floor(v[1]) || v[1] < -1 || v[1] > 2e9) {
      throw IoError(where, "the id must be an integer >= -1");
    }
    row(v);
  }
}

std::string Header(const std::vector<std::string>& header) {
  std::string out;
  for (const std::string& h : header) out += "# " + h + "\n";
  return out;
}

}  // namespace

std::vector<sensor::SegmentObservation> ParseSegmentTracks(const std::string& text,
                                                           const std::string& name) {
  std::vector<sensor::SegmentObservation> out;
  ParseRows(text, name, 6, [&](const std::vector<double>& v) {
    sensor::SegmentObservation o;
    o.frame = static_cast<int>(v[0]);
    o.line_id = static_cast<int>(v[1]);
    o.s_px = Eigen::Vector2d(v[2], v[3]);
    o.e_px = Eigen::Vector2d(v[4], v[5]);
    out.push_back(o);
  });
  return out;
}

std::vector<sensor::SegmentObservation> ReadSegmentTracks(const std::string& path) {
  return ParseSegmentTracks(ReadText(path), path);
}

void WriteSegmentTracks(const std::string& path,
                        const std::vector<sensor::SegmentObservation>& observations,
                        const std::vector<std::string>& header) {
  std::string out = Header(header) + "# frame line_id su sv eu ev [px]\n";
  char buf[160];
  for (const auto& o : observations) {
    std::snprintf(buf, sizeof(buf), "%d %d %.3f %.3f %.3f %.3f\n", o.frame, o.line_id, o.s_px.x(),
                  o.s_px.y(), o.e_px.x(), o.e_px.y());
    out += buf;
  }
  WriteFileAtomically(path, out);
}

std::vector<sensor::PointObservation> ParsePointTracks(const std::string& text,
                                                       const std::string& name) {
  std::vector<sensor::PointObservation> out;
  ParseRows(text, name, 4, [&](const std::vector<double>& v) {
    sensor::PointObservation o;
    o.frame = static_cast<int>(v[0]);
    o.point_id = static_cast<int>(v[1]);
    o.uv = Eigen::Vector2d(v[2], v[3]);
    out.push_back(o);
  });
  return out;
}

std::vector<sensor::PointObservation> ReadPointTracks(const std::string& path) {
  return ParsePointTracks(ReadText(path), path);
}

void WritePointTracks(const std::string& path,
                      const std::vector<sensor::PointObservation>& observations,
                      const std::vector<std::string>& header) {
  std::string out = Header(header) + "# frame point_id u v [px]\n";
  char buf[120];
  for (const auto& o : observations) {
    std::snprintf(buf, sizeof(buf), "%d %d %.3f %.3f\n", o.frame, o.point_id, o.uv.x(), o.uv.y());
    out += buf;
  }
  WriteFileAtomically(path, out);
}

}  // namespace io
}  // namespace plucker
