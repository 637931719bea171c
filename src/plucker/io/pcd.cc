#include "plucker/io/pcd.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "plucker/io/binary_scalar.h"
#include "plucker/io/kitti_lidar.h"

namespace plucker {
namespace io {
namespace {

constexpr std::size_t kMaxHeaderBytes = 1 << 16;
constexpr std::size_t kMaxPoints = std::size_t{1} << 31;

std::vector<std::string> SplitWords(const std::string& line) {
  std::vector<std::string> words;
  std::istringstream in(line);
  std::string w;
  while (in >> w) words.push_back(w);
  return words;
}

bool ParseSize(const std::string& s, std::size_t* v) {
  if (s.empty() || s.size() > 18) return false;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
  }
  *v = static_cast<std::size_t>(std::strtoull(s.c_str(), nullptr, 10));
  return true;
}

bool ParseNumber(const char* begin, std::size_t len, double* v) {
  char buf[72];
  if (len == 0 || len >= sizeof(buf)) return false;
  std::memcpy(buf, begin, len);
  buf[len] = '\0';
  char* end = nullptr;
  *v = std::strtod(buf, &end);
  return end == buf + len;
}

void StoreLE(std::uint64_t u, int size, std::string* out) {
  for (int i = 0; i < size; ++i) out->push_back(static_cast<char>((u >> (8 * i)) & 0xFF));
}
void StoreFloat(float f, std::string* out) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  StoreLE(u, 4, out);
}
void StoreDouble(double d, std::string* out) {
  std::uint64_t u;
  std::memcpy(&u, &d, 8);
  StoreLE(u, 8, out);
}

int FieldIndex(const PcdHeader& h, const char* name) {
  for (std::size_t i = 0; i < h.fields.size(); ++i) {
    if (h.fields[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

// Converts the raw per-point values into a scan: drops non-finite points, normalises times.
struct Channels {
  int x = -1, y = -1, z = -1, intensity = -1, ring = -1, time = -1;
};

}  // namespace

bool PcdHeader::HasField(const std::string& name) const {
  for (const PcdField& f : fields) {
    if (f.name == name) return true;
  }
  return false;
}

bool LzfDecompress(const unsigned char* in, std::size_t in_size, std::size_t expected_size,
                   std::string* out) {
  out->assign(expected_size, '\0');
  unsigned char* o = reinterpret_cast<unsigned char*>(&(*out)[0]);
  std::size_t ip = 0, op = 0;
  while (ip < in_size) {
    const unsigned int ctrl = in[ip++];
    if (ctrl < 32) {  // literal run of ctrl + 1 bytes
      const std::size_t len = ctrl + 1;
      if (ip + len > in_size || op + len > expected_size) return false;
      std::memcpy(o + op, in + ip, len);
      ip += len;
      op += len;
    } else {  // back reference
      std::size_t len = ctrl >> 5;
      if (len == 7) {
        if (ip >= in_size) return false;
        len += in[ip++];
      }
      len += 2;
      if (ip >= in_size) return false;
      const std::size_t offset = ((ctrl & 0x1fu) << 8) + in[ip++] + 1;
      if (offset > op || op + len > expected_size) return false;
      for (std::size_t k = 0; k < len; ++k, ++op) o[op] = o[op - offset];  // may overlap
    }
  }
  return op == expected_size;
}

PcdHeader ParsePcdHeader(const std::string& bytes, const std::string& name) {
  PcdHeader h;
  bool have_fields = false, have_size = false, have_type = false, have_count = false;
  bool have_width = false, have_height = false, have_points = false, have_data = false;
  std::vector<std::string> sizes, types, counts;
  std::size_t pos = 0;
  int line_no = 0;
  while (pos < bytes.size() && !have_data) {
    if (pos > kMaxHeaderBytes) throw IoError(name, "PCD header: no DATA line in the first 64 KB");
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    const std::string line = bytes.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    const std::vector<std::string> w = SplitWords(line);
    if (w.empty() || w[0][0] == '#') continue;
    const std::string where = "PCD header line " + std::to_string(line_no) + " (" + w[0] + "): ";
    const std::string& key = w[0];
    if (key == "VERSION") {
      if (w.size() != 2) throw IoError(name, where + "expected one value");
      h.version = w[1];
    } else if (key == "FIELDS" || key == "COLUMNS") {
      if (w.size() < 2) throw IoError(name, where + "no field names");
      for (std::size_t i = 1; i < w.size(); ++i) {
        PcdField f;
        f.name = w[i];
        h.fields.push_back(f);
      }
      have_fields = true;
    } else if (key == "SIZE") {
      sizes.assign(w.begin() + 1, w.end());
      have_size = true;
    } else if (key == "TYPE") {
      types.assign(w.begin() + 1, w.end());
      have_type = true;
    } else if (key == "COUNT") {
      counts.assign(w.begin() + 1, w.end());
      have_count = true;
    } else if (key == "WIDTH" || key == "HEIGHT" || key == "POINTS") {
      std::size_t v;
      if (w.size() != 2 || !ParseSize(w[1], &v)) {
        throw IoError(name, where + "expected one non-negative integer");
      }
      if (key == "WIDTH") h.width = v, have_width = true;
      if (key == "HEIGHT") h.height = v, have_height = true;
      if (key == "POINTS") h.points = v, have_points = true;
    } else if (key == "VIEWPOINT") {
      if (w.size() != 8) throw IoError(name, where + "expected 7 numbers");
      for (std::size_t i = 1; i < 8; ++i) {
        double v;
        if (!ParseNumber(w[i].data(), w[i].size(), &v) || !std::isfinite(v)) {
          throw IoError(name, where + "malformed number '" + w[i] + "'");
        }
      }
    } else if (key == "DATA") {
      if (w.size() != 2) throw IoError(name, where + "expected ascii, binary or binary_compressed");
      if (w[1] == "ascii") {
        h.encoding = PcdEncoding::kAscii;
      } else if (w[1] == "binary") {
        h.encoding = PcdEncoding::kBinary;
      } else if (w[1] == "binary_compressed") {
        h.encoding = PcdEncoding::kBinaryCompressed;
      } else {
        throw IoError(name, where + "unknown data encoding '" + w[1] + "'");
      }
      have_data = true;
      h.data_offset = std::min(pos, bytes.size());
    } else {
      throw IoError(name, where + "unknown header entry (not a PCD file?)");
    }
  }
  if (!have_data) throw IoError(name, "PCD header: missing DATA line (not a PCD file?)");
  if (!have_fields) throw IoError(name, "PCD header: missing FIELDS");
  if (!have_size) throw IoError(name, "PCD header: missing SIZE");
  if (!have_type) throw IoError(name, "PCD header: missing TYPE");
  if (!have_width) throw IoError(name, "PCD header: missing WIDTH");
  if (!have_height) throw IoError(name, "PCD header: missing HEIGHT");
  const std::size_t nf = h.fields.size();
  if (sizes.size() != nf) {
    throw IoError(name, "PCD header: SIZE has " + std::to_string(sizes.size()) + " entries for " +
                            std::to_string(nf) + " FIELDS");
  }
  if (types.size() != nf) {
    throw IoError(name, "PCD header: TYPE has " + std::to_string(types.size()) + " entries for " +
                            std::to_string(nf) + " FIELDS");
  }
  if (have_count && counts.size() != nf) {
    throw IoError(name, "PCD header: COUNT has " + std::to_string(counts.size()) + " entries for " +
                            std::to_string(nf) + " FIELDS");
  }
  for (std::size_t i = 0; i < nf; ++i) {
    PcdField& f = h.fields[i];
    std::size_t s = 0, c = 1;
    if (!ParseSize(sizes[i], &s) || (s != 1 && s != 2 && s != 4 && s != 8)) {
      throw IoError(name, "PCD header: field '" + f.name + "' has invalid SIZE '" + sizes[i] + "'");
    }
    if (types[i].size() != 1 || std::string("FIU").find(types[i][0]) == std::string::npos) {
      throw IoError(name, "PCD header: field '" + f.name + "' has invalid TYPE '" + types[i] + "'");
    }
    if (have_count && (!ParseSize(counts[i], &c) || c == 0 || c > 100000)) {
      throw IoError(name,
                    "PCD header: field '" + f.name + "' has invalid COUNT '" + counts[i] + "'");
    }
    f.size = static_cast<int>(s);
    f.type = types[i][0];
    f.count = static_cast<int>(c);
    if (f.type == 'F' && f.size != 4 && f.size != 8) {
      throw IoError(name, "PCD header: float field '" + f.name + "' must have SIZE 4 or 8");
    }
  }
  if (h.height != 0 && h.width > kMaxPoints / h.height) {
    throw IoError(name, "PCD header: WIDTH*HEIGHT too large");
  }
  const std::size_t wh = h.width * h.height;
  if (have_points && h.points != wh) {
    throw IoError(name, "PCD header: POINTS " + std::to_string(h.points) + " != WIDTH*HEIGHT " +
                            std::to_string(wh));
  }
  h.points = wh;
  for (const char* required : {"x", "y", "z"}) {
    if (!h.HasField(required)) {
      throw IoError(name, std::string("PCD header: required field '") + required + "' missing");
    }
  }
  return h;
}

PcdHeader ReadPcdHeader(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, std::string("cannot open: ") + std::strerror(errno));
  std::string head(kMaxHeaderBytes + 1, '\0');
  in.read(&head[0], static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return ParsePcdHeader(head, path);
}

LidarScan ParsePcd(const std::string& bytes, const std::string& name, ScanReadStats* stats) {
  LidarScan scan;
  ParsePcd(bytes, name, &scan, stats);
  return scan;
}

void ParsePcd(const std::string& bytes, const std::string& name, LidarScan* out,
              ScanReadStats* stats) {
  const PcdHeader h = ParsePcdHeader(bytes, name);
  const std::size_t n = h.points;
  if (n == 0) throw IoError(name, "empty point cloud (0 points)");

  // Element offsets within a point record (binary) or value index (ascii).
  std::vector<std::size_t> offset(h.fields.size()), value_index(h.fields.size());
  std::size_t point_bytes = 0, values_per_point = 0;
  for (std::size_t i = 0; i < h.fields.size(); ++i) {
    offset[i] = point_bytes;
    value_index[i] = values_per_point;
    point_bytes += static_cast<std::size_t>(h.fields[i].size) * h.fields[i].count;
    values_per_point += h.fields[i].count;
  }
  Channels ch;
  ch.x = FieldIndex(h, "x");
  ch.y = FieldIndex(h, "y");
  ch.z = FieldIndex(h, "z");
  ch.intensity = FieldIndex(h, "intensity");
  ch.ring = FieldIndex(h, "ring");
  ch.time = FieldIndex(h, "time");
  if (ch.time < 0) ch.time = FieldIndex(h, "t");
  if (ch.time < 0) ch.time = FieldIndex(h, "timestamp");
  for (int f : {ch.x, ch.y, ch.z}) {
    if (h.fields[f].type != 'F') {
      throw IoError(name, "field '" + h.fields[f].name + "' must be a float (TYPE F)");
    }
  }
  const bool time_in_ns = ch.time >= 0 && h.fields[ch.time].type != 'F';

  const std::size_t data_size = bytes.size() - h.data_offset;
  const unsigned char* data = reinterpret_cast<const unsigned char*>(bytes.data()) + h.data_offset;
  std::string decompressed;
  // value(point, field): reads element 0 of the field for the point.
  std::vector<double> values;  // ascii: n * values_per_point (only when ascii)
  if (h.encoding == PcdEncoding::kBinary) {
    if (point_bytes != 0 && n > data_size / point_bytes) {
      throw IoError(name, "truncated binary data: " + std::to_string(n) + " points of " +
                              std::to_string(point_bytes) + " bytes need " +
                              std::to_string(n * point_bytes) + " bytes, file has " +
                              std::to_string(data_size));
    }
  } else if (h.encoding == PcdEncoding::kBinaryCompressed) {
    if (data_size < 8) throw IoError(name, "truncated binary_compressed data (no size words)");
    const std::uint32_t csize = static_cast<std::uint32_t>(LoadLittleEndianScalar(data, 4, 'U'));
    const std::uint32_t usize =
        static_cast<std::uint32_t>(LoadLittleEndianScalar(data + 4, 4, 'U'));
    if (n > std::numeric_limits<std::size_t>::max() / point_bytes || usize != n * point_bytes) {
      throw IoError(name, "binary_compressed: uncompressed size " + std::to_string(usize) +
                              " != POINTS * point size " + std::to_string(n * point_bytes));
    }
    if (csize > data_size - 8) {
      throw IoError(name, "truncated binary_compressed data: " + std::to_string(csize) +
                              " compressed bytes declared, " + std::to_string(data_size - 8) +
                              " present");
    }
    // LZF expands at most ~88x (a 2-byte back reference yields <= 264 bytes): bound the
    // allocation before decompressing corrupt input.
    if (static_cast<std::uint64_t>(usize) > static_cast<std::uint64_t>(csize) * 132 + 64) {
      throw IoError(name, "binary_compressed: corrupt sizes (uncompressed size impossible)");
    }
    if (!LzfDecompress(data + 8, csize, usize, &decompressed)) {
      throw IoError(name, "binary_compressed: corrupt LZF data");
    }
  } else {
    // ASCII: whitespace-separated numbers, values_per_point per point.
    if (n > std::numeric_limits<std::size_t>::max() / values_per_point ||
        n * values_per_point > (data_size + 1) / 2) {
      throw IoError(name, "truncated ascii data: " + std::to_string(n) + " points declared, " +
                              "file too short");
    }
    const std::size_t need = n * values_per_point;
    values.reserve(need);
    std::size_t p = 0;
    const char* text = reinterpret_cast<const char*>(data);
    while (values.size() < need) {
      while (p < data_size && std::isspace(static_cast<unsigned char>(text[p]))) ++p;
      if (p >= data_size) {
        throw IoError(name,
                      "truncated ascii data: " + std::to_string(values.size() / values_per_point) +
                          " complete points of " + std::to_string(n) + " declared");
      }
      const std::size_t b = p;
      while (p < data_size && !std::isspace(static_cast<unsigned char>(text[p]))) ++p;
      double v;
      if (!ParseNumber(text + b, p - b, &v)) {
        throw IoError(name, "ascii data: malformed number '" +
                                std::string(text + b, std::min<std::size_t>(p - b, 32)) +
                                "' at point " + std::to_string(values.size() / values_per_point));
      }
      values.push_back(v);
    }
  }

  auto value = [&](std::size_t i, int f) -> double {
    const PcdField& fd = h.fields[f];
    switch (h.encoding) {
      case PcdEncoding::kAscii:
        return values[i * values_per_point + value_index[f]];
      case PcdEncoding::kBinary:
        return LoadLittleEndianScalar(data + i * point_bytes + offset[f], fd.size, fd.type);
      case PcdEncoding::kBinaryCompressed:
      default: {
        // Field-major: all elements of field 0 for every point, then field 1, ...
        const std::size_t base = offset[f] * n;
        const std::size_t elem = static_cast<std::size_t>(fd.size) * fd.count;
        return LoadLittleEndianScalar(
            reinterpret_cast<const unsigned char*>(decompressed.data()) + base + i * elem, fd.size,
            fd.type);
      }
    }
  };

  LidarScan& scan = *out;  // its channels' capacity is reused
  scan.points.clear();
  scan.intensity.clear();
  scan.ring.clear();
  scan.time.clear();
  scan.timestamp = 0.0;
  scan.points.reserve(n);
  if (ch.intensity >= 0) scan.intensity.reserve(n);
  if (ch.ring >= 0) scan.ring.reserve(n);
  if (ch.time >= 0) scan.time.reserve(n);
  std::size_t dropped = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p(value(i, ch.x), value(i, ch.y), value(i, ch.z));
    if (!p.allFinite()) {
      ++dropped;
      continue;
    }
    scan.points.push_back(p);
    if (ch.intensity >= 0) {
      const double v = value(i, ch.intensity);
      scan.intensity.push_back(std::isfinite(v) ? static_cast<float>(v) : 0.0f);
    }
    if (ch.ring >= 0) {
      const double r = value(i, ch.ring);
      scan.ring.push_back(std::isfinite(r) && r >= 0.0 && r < 65536.0 ? static_cast<int>(r) : -1);
    }
    if (ch.time >= 0) {
      double t = value(i, ch.time);
      if (time_in_ns) t *= 1e-9;
      scan.time.push_back(t);
    }
  }
  if (stats) {
    stats->points_in_file = n;
    stats->non_finite_dropped = dropped;
  }
  if (scan.points.empty()) {
    throw IoError(name, "no finite point (" + std::to_string(n) + " points, all NaN/Inf)");
  }
  if (!scan.time.empty()) {
    double t_min = std::numeric_limits<double>::infinity();
    double t_max = -t_min;
    for (double& t : scan.time) {
      if (!std::isfinite(t))
        throw IoError(name, "non-finite point time in field '" + h.fields[ch.time].name + "'");
      t_min = std::min(t_min, t);
      t_max = std::max(t_max, t);
    }
    if (scan.time.size() > 1 && t_max == t_min)
      throw IoError(name, "time field '" + h.fields[ch.time].name + "' is constant (all " +
                              std::to_string(t_min) + " over " + std::to_string(scan.time.size()) +
                              " points): no per-point time; drop the field to deskew from "
                              "the azimuth (constant velocity)");
    if (t_min < 0.0 || t_min > 1.0) {
      for (double& t : scan.time) t -= t_min;
      if (t_min > 1.0) scan.timestamp = t_min;
    }
  }
}

LidarScan ReadPcd(const std::string& path, ScanReadStats* stats) {
  return ParsePcd(ReadFileToString(path), path, stats);
}

std::string SerializePcd(const LidarScan& scan, PcdEncoding encoding) {
  if (encoding == PcdEncoding::kBinaryCompressed) {
    throw IoError("<pcd>", "writing binary_compressed is not supported; use binary or ascii");
  }
  const std::size_t n = scan.size();
  const bool has_i = !scan.intensity.empty() && scan.intensity.size() == n;
  const bool has_r = !scan.ring.empty() && scan.ring.size() == n;
  const bool has_t = !scan.time.empty() && scan.time.size() == n;
  std::string fields = "x y z", sizes = "4 4 4", types = "F F F", counts = "1 1 1";
  if (has_i) fields += " intensity", sizes += " 4", types += " F", counts += " 1";
  if (has_r) fields += " ring", sizes += " 2", types += " U", counts += " 1";
  if (has_t) fields += " time", sizes += " 8", types += " F", counts += " 1";
  std::string out;
  out += "# .PCD v0.7 - Point Cloud Data file format (written by plucker)\n";
  out += "VERSION 0.7\nFIELDS " + fields + "\nSIZE " + sizes + "\nTYPE " + types + "\nCOUNT " +
         counts + "\nWIDTH " + std::to_string(n) + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " +
         std::to_string(n) + "\nDATA " +
         (encoding == PcdEncoding::kAscii ? std::string("ascii") : std::string("binary")) + "\n";
  char buf[128];
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f p = scan.points[i].cast<float>();
    const int ring = has_r ? std::max(0, std::min(65535, scan.ring[i])) : 0;
    if (encoding == PcdEncoding::kAscii) {
      std::snprintf(buf, sizeof(buf), "%.9g %.9g %.9g", p.x(), p.y(), p.z());
      out += buf;
      if (has_i) std::snprintf(buf, sizeof(buf), " %.9g", scan.intensity[i]), out += buf;
      if (has_r) std::snprintf(buf, sizeof(buf), " %d", ring), out += buf;
      if (has_t) std::snprintf(buf, sizeof(buf), " %.17g", scan.time[i]), out += buf;
      out += '\n';
    } else {
      StoreFloat(p.x(), &out);
      StoreFloat(p.y(), &out);
      StoreFloat(p.z(), &out);
      if (has_i) StoreFloat(scan.intensity[i], &out);
      if (has_r) StoreLE(static_cast<std::uint64_t>(ring), 2, &out);
      if (has_t) StoreDouble(scan.time[i], &out);
    }
  }
  return out;
}

void WritePcd(const std::string& path, const LidarScan& scan, PcdEncoding encoding) {
  if (encoding == PcdEncoding::kBinaryCompressed) {
    throw IoError(path, "writing binary_compressed is not supported; use binary or ascii");
  }
  WriteFileAtomically(path, SerializePcd(scan, encoding));
}

}  // namespace io
}  // namespace plucker
