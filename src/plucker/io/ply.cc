#include "plucker/io/ply.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>

#include "plucker/io/binary_scalar.h"
#include "plucker/io/kitti_lidar.h"

namespace plucker {
namespace io {
namespace {

struct PlyProperty {
  std::string name;
  int size = 4;
  char type = 'F';  // F float, I signed, U unsigned
};

bool PlyType(const std::string& t, PlyProperty* p) {
  static const struct {
    const char* name;
    int size;
    char type;
  } kTypes[] = {{"char", 1, 'I'},  {"int8", 1, 'I'},    {"uchar", 1, 'U'},  {"uint8", 1, 'U'},
                {"short", 2, 'I'}, {"int16", 2, 'I'},   {"ushort", 2, 'U'}, {"uint16", 2, 'U'},
                {"int", 4, 'I'},   {"int32", 4, 'I'},   {"uint", 4, 'U'},   {"uint32", 4, 'U'},
                {"float", 4, 'F'}, {"float32", 4, 'F'}, {"double", 8, 'F'}, {"float64", 8, 'F'}};
  for (const auto& k : kTypes) {
    if (t == k.name) {
      p->size = k.size;
      p->type = k.type;
      return true;
    }
  }
  return false;
}

void StoreFloat(float f, std::string* out) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  for (int i = 0; i < 4; ++i) out->push_back(static_cast<char>((u >> (8 * i)) & 0xFF));
}

}  // namespace

std::string SerializePly(const std::vector<Eigen::Vector3d>& points,
                         const std::vector<float>& intensity, PlyFormat format) {
  const bool has_i = !intensity.empty();
  std::string out = "ply\nformat ";
  out += format == PlyFormat::kAscii ? "ascii 1.0\n" : "binary_little_endian 1.0\n";
  out += "comment written by plucker\nelement vertex " + std::to_string(points.size()) +
         "\nproperty float x\nproperty float y\nproperty float z\n";
  if (has_i) out += "property float intensity\n";
  out += "end_header\n";
  char buf[128];
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f p = points[i].cast<float>();
    if (format == PlyFormat::kAscii) {
      if (has_i) {
        std::snprintf(buf, sizeof(buf), "%.9g %.9g %.9g %.9g\n", p.x(), p.y(), p.z(), intensity[i]);
      } else {
        std::snprintf(buf, sizeof(buf), "%.9g %.9g %.9g\n", p.x(), p.y(), p.z());
      }
      out += buf;
    } else {
      StoreFloat(p.x(), &out);
      StoreFloat(p.y(), &out);
      StoreFloat(p.z(), &out);
      if (has_i) StoreFloat(intensity[i], &out);
    }
  }
  return out;
}

void WritePly(const std::string& path, const std::vector<Eigen::Vector3d>& points,
              const std::vector<float>& intensity, PlyFormat format) {
  if (!intensity.empty() && intensity.size() != points.size()) {
    throw IoError(path, "cannot write PLY: " + std::to_string(intensity.size()) +
                            " intensities for " + std::to_string(points.size()) + " points");
  }
  WriteFileAtomically(path, SerializePly(points, intensity, format));
}

void WritePly(const std::string& path, const LidarScan& cloud, PlyFormat format) {
  WritePly(path, cloud.points,
           cloud.intensity.size() == cloud.points.size() ? cloud.intensity : std::vector<float>{},
           format);
}

LidarScan ParsePly(const std::string& bytes, const std::string& name, ScanReadStats* stats) {
  std::size_t pos = 0;
  auto next_line = [&](std::string* line) {
    if (pos >= bytes.size() || pos > (1 << 16)) return false;
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    *line = bytes.substr(pos, eol - pos);
    if (!line->empty() && line->back() == '\r') line->pop_back();
    pos = eol + 1;
    return true;
  };
  std::string line;
  if (!next_line(&line) || line != "ply") throw IoError(name, "not a PLY file (no 'ply' magic)");
  bool ascii = false, have_format = false, in_vertex = false, seen_vertex = false, ended = false;
  std::size_t count = 0;
  std::vector<PlyProperty> props;
  while (next_line(&line)) {
    std::istringstream in(line);
    std::string key;
    in >> key;
    if (key.empty() || key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      std::string fmt, ver;
      in >> fmt >> ver;
      if (fmt == "ascii") {
        ascii = true;
      } else if (fmt == "binary_little_endian") {
        ascii = false;
      } else if (fmt == "binary_big_endian") {
        throw IoError(name, "PLY binary_big_endian is not supported (convert to little endian)");
      } else {
        throw IoError(name, "PLY header: unknown format '" + fmt + "'");
      }
      have_format = true;
    } else if (key == "element") {
      std::string el, n;
      in >> el >> n;
      if (in_vertex || seen_vertex) {
        in_vertex = false;  // elements after the vertices are ignored
        continue;
      }
      if (el != "vertex") {
        throw IoError(name, "PLY: element '" + el + "' before 'vertex' is not supported");
      }
      if (n.empty() || n.size() > 12 || n.find_first_not_of("0123456789") != std::string::npos) {
        throw IoError(name, "PLY header: malformed vertex count '" + n + "'");
      }
      count = std::stoull(n);
      in_vertex = seen_vertex = true;
    } else if (key == "property") {
      if (!in_vertex) continue;
      std::string type, pname;
      in >> type >> pname;
      if (type == "list") throw IoError(name, "PLY: list property in the vertex element");
      PlyProperty p;
      p.name = pname;
      if (!PlyType(type, &p) || pname.empty()) {
        throw IoError(name, "PLY header: malformed property '" + line + "'");
      }
      props.push_back(p);
    } else if (key == "end_header") {
      ended = true;
      break;
    } else {
      throw IoError(name, "PLY header: unknown line '" + line.substr(0, 40) + "'");
    }
  }
  if (!ended) throw IoError(name, "PLY header: missing end_header");
  if (!have_format) throw IoError(name, "PLY header: missing format");
  if (!seen_vertex) throw IoError(name, "PLY header: no vertex element");
  int ix = -1, iy = -1, iz = -1, ii = -1;
  std::size_t record = 0;
  std::vector<std::size_t> offsets;
  for (std::size_t k = 0; k < props.size(); ++k) {
    offsets.push_back(record);
    record += props[k].size;
    if (props[k].name == "x") ix = static_cast<int>(k);
    if (props[k].name == "y") iy = static_cast<int>(k);
    if (props[k].name == "z") iz = static_cast<int>(k);
    if (props[k].name == "intensity") ii = static_cast<int>(k);
  }
  if (ix < 0 || iy < 0 || iz < 0) throw IoError(name, "PLY: vertex lacks x, y or z");
  if (count == 0) throw IoError(name, "empty point cloud (0 vertices)");
  const std::size_t data_size = bytes.size() - std::min(pos, bytes.size());
  const char* data = bytes.data() + std::min(pos, bytes.size());
  std::vector<double> row(props.size());
  LidarScan cloud;
  std::size_t dropped = 0, tp = 0;
  if (!ascii) {
    if (count > data_size / record) {
      throw IoError(name, "truncated binary data: " + std::to_string(count) + " vertices of " +
                              std::to_string(record) + " bytes, " + std::to_string(data_size) +
                              " bytes present");
    }
  } else if (count > data_size / (2 * props.size()) + 1) {
    throw IoError(
        name, "truncated ascii data: file too short for " + std::to_string(count) + " vertices");
  }
  cloud.points.reserve(count);
  if (ii >= 0) cloud.intensity.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    if (ascii) {
      for (std::size_t k = 0; k < props.size(); ++k) {
        while (tp < data_size && std::isspace(static_cast<unsigned char>(data[tp]))) ++tp;
        const std::size_t b = tp;
        while (tp < data_size && !std::isspace(static_cast<unsigned char>(data[tp]))) ++tp;
        if (b == tp) {
          throw IoError(name, "truncated ascii data at vertex " + std::to_string(i));
        }
        char buf[72];
        const std::size_t len = tp - b;
        char* end = nullptr;
        if (len < sizeof(buf)) {
          std::memcpy(buf, data + b, len);
          buf[len] = '\0';
          row[k] = std::strtod(buf, &end);
        }
        if (len >= sizeof(buf) || end != buf + len) {
          throw IoError(name, "malformed number at vertex " + std::to_string(i));
        }
      }
    } else {
      const unsigned char* r = reinterpret_cast<const unsigned char*>(data) + i * record;
      for (std::size_t k = 0; k < props.size(); ++k) {
        row[k] = LoadLittleEndianScalar(r + offsets[k], props[k].size, props[k].type);
      }
    }
    const Eigen::Vector3d p(row[ix], row[iy], row[iz]);
    if (!p.allFinite()) {
      ++dropped;
      continue;
    }
    cloud.points.push_back(p);
    if (ii >= 0)
      cloud.intensity.push_back(std::isfinite(row[ii]) ? static_cast<float>(row[ii]) : 0.f);
  }
  if (stats) {
    stats->points_in_file = count;
    stats->non_finite_dropped = dropped;
  }
  if (cloud.points.empty()) throw IoError(name, "no finite vertex");
  return cloud;
}

LidarScan ReadPly(const std::string& path, ScanReadStats* stats) {
  return ParsePly(ReadFileToString(path), path, stats);
}

void WriteSegmentsPly(const std::string& path,
                      const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& segments) {
  std::ostringstream out;
  out << "ply\nformat ascii 1.0\nelement vertex " << 2 * segments.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nelement edge " << segments.size()
      << "\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  out.precision(9);
  for (const auto& [a, b] : segments) {
    out << a.x() << ' ' << a.y() << ' ' << a.z() << '\n';
    out << b.x() << ' ' << b.y() << ' ' << b.z() << '\n';
  }
  for (std::size_t i = 0; i < segments.size(); ++i) out << 2 * i << ' ' << 2 * i + 1 << '\n';
  WriteFileAtomically(path, out.str());
}

}  // namespace io
}  // namespace plucker
