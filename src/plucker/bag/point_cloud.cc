#include "plucker/bag/point_cloud.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace plucker {
namespace bag {
namespace {

std::size_t TypeSize(std::uint8_t type) {
  switch (static_cast<FieldType>(type)) {
    case FieldType::kInt8:
    case FieldType::kUint8:
      return 1;
    case FieldType::kInt16:
    case FieldType::kUint16:
      return 2;
    case FieldType::kInt32:
    case FieldType::kUint32:
    case FieldType::kFloat32:
      return 4;
    case FieldType::kFloat64:
      return 8;
  }
  return 0;
}

bool IsFloat(std::uint8_t type) {
  return type == static_cast<std::uint8_t>(FieldType::kFloat32) ||
         type == static_cast<std::uint8_t>(FieldType::kFloat64);
}

// Element 0 of a field of the point at p (little-endian, the host order on the targets built).
double Load(const std::uint8_t* p, std::uint8_t type) {
  switch (static_cast<FieldType>(type)) {
    case FieldType::kInt8:
      return static_cast<std::int8_t>(*p);
    case FieldType::kUint8:
      return *p;
    case FieldType::kInt16: {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case FieldType::kUint16: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case FieldType::kInt32: {
      std::int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case FieldType::kUint32: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case FieldType::kFloat32: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case FieldType::kFloat64: {
      double v;
      std::memcpy(&v, p, 8);
      return v;
    }
  }
  return 0.0;
}

const CloudField* Find(const CloudLayout& layout, const char* name) {
  for (const CloudField& f : layout.fields)
    if (f.name == name) return &f;
  return nullptr;
}

std::string FieldNames(const CloudLayout& layout) {
  std::string names;
  for (const CloudField& f : layout.fields) names += (names.empty() ? "" : ", ") + f.name;
  return names.empty() ? "none" : names;
}

}  // namespace

std::string CloudToScan(const CloudLayout& layout, const std::uint8_t* data, std::size_t size,
                        sensor::LidarScan* scan, CloudStats* stats) {
  if (layout.big_endian) return "big-endian point data is not supported (is_bigendian = true)";
  const CloudField* x = Find(layout, "x");
  const CloudField* y = Find(layout, "y");
  const CloudField* z = Find(layout, "z");
  if (!x || !y || !z) return "no x, y, z fields (fields: " + FieldNames(layout) + ")";
  const CloudField* intensity = Find(layout, "intensity");
  const CloudField* ring = Find(layout, "ring");
  const CloudField* time = Find(layout, "time");
  if (!time) time = Find(layout, "t");
  if (!time) time = Find(layout, "timestamp");
  for (const CloudField* f : {x, y, z, intensity, ring, time}) {
    if (!f) continue;
    const std::size_t bytes = TypeSize(f->datatype);
    if (bytes == 0)
      return "field '" + f->name + "' has unknown datatype " + std::to_string(f->datatype);
    if (f->count == 0) return "field '" + f->name + "' has count 0";
    if (static_cast<std::size_t>(f->offset) + bytes > layout.point_step)
      return "field '" + f->name + "' (offset " + std::to_string(f->offset) + ", " +
             std::to_string(bytes) + " bytes) does not fit in point_step " +
             std::to_string(layout.point_step);
  }
  const std::size_t width = layout.width, height = layout.height;
  const std::size_t n = width * height;
  if (n == 0) return "empty cloud (width * height = 0)";
  if (height > 0 && width > 0 &&
      (layout.row_step < static_cast<std::size_t>(layout.point_step) * width))
    return "row_step " + std::to_string(layout.row_step) + " is less than point_step * width (" +
           std::to_string(layout.point_step) + " * " + std::to_string(width) + ")";
  if (height > 0 &&
      (size / std::max<std::size_t>(layout.row_step, 1) < height || layout.row_step == 0))
    return "data has " + std::to_string(size) + " bytes, " + std::to_string(height) +
           " rows of row_step " + std::to_string(layout.row_step) + " need more";

  scan->points.clear();
  scan->intensity.clear();
  scan->ring.clear();
  scan->time.clear();
  scan->timestamp = 0.0;
  scan->points.reserve(n);
  if (intensity) scan->intensity.reserve(n);
  if (ring) scan->ring.reserve(n);
  if (time) scan->time.reserve(n);
  const bool time_in_ns = time && !IsFloat(time->datatype);
  std::size_t dropped = 0;
  for (std::size_t r = 0; r < height; ++r) {
    const std::uint8_t* row = data + r * layout.row_step;
    for (std::size_t c = 0; c < width; ++c) {
      const std::uint8_t* p = row + c * layout.point_step;
      const Eigen::Vector3d v(Load(p + x->offset, x->datatype), Load(p + y->offset, y->datatype),
                              Load(p + z->offset, z->datatype));
      if (!v.allFinite()) {
        ++dropped;
        continue;
      }
      scan->points.push_back(v);
      if (intensity) {
        const double i = Load(p + intensity->offset, intensity->datatype);
        scan->intensity.push_back(std::isfinite(i) ? static_cast<float>(i) : 0.0f);
      }
      if (ring) {
        const double b = Load(p + ring->offset, ring->datatype);
        scan->ring.push_back(std::isfinite(b) && b >= 0.0 && b < 65536.0 ? static_cast<int>(b)
                                                                         : -1);
      }
      if (time) {
        const double t = Load(p + time->offset, time->datatype);
        scan->time.push_back(time_in_ns ? t * 1e-9 : t);
      }
    }
  }
  if (stats) {
    stats->points = n;
    stats->non_finite_dropped = dropped;
  }
  if (scan->points.empty()) return "no finite point (" + std::to_string(n) + " points)";
  if (!scan->time.empty()) {
    double t_min = std::numeric_limits<double>::infinity();
    double t_max = -t_min;
    for (double t : scan->time) {
      if (!std::isfinite(t)) return "non-finite point time in field '" + time->name + "'";
      t_min = std::min(t_min, t);
      t_max = std::max(t_max, t);
    }
    if (scan->time.size() > 1 && t_max == t_min)
      return "time field '" + time->name + "' is constant (all " + std::to_string(t_min) +
             "): no per-point time";
    if (t_min < 0.0 || t_min > 1.0) {
      for (double& t : scan->time) t -= t_min;
      if (t_min > 1.0) scan->timestamp = t_min;
    }
  }
  return "";
}

CloudLayout ScanLayout(const sensor::LidarScan& scan) {
  CloudLayout layout;
  auto add = [&layout](const char* name, FieldType type) {
    layout.fields.push_back({name, layout.point_step, static_cast<std::uint8_t>(type), 1});
    layout.point_step += static_cast<std::uint32_t>(TypeSize(static_cast<std::uint8_t>(type)));
  };
  add("x", FieldType::kFloat32);
  add("y", FieldType::kFloat32);
  add("z", FieldType::kFloat32);
  if (scan.intensity.size() == scan.size()) add("intensity", FieldType::kFloat32);
  if (scan.time.size() == scan.size() && !scan.empty()) add("time", FieldType::kFloat64);
  if (scan.ring.size() == scan.size() && !scan.empty()) add("ring", FieldType::kUint16);
  layout.width = static_cast<std::uint32_t>(scan.size());
  layout.row_step = layout.point_step * layout.width;
  return layout;
}

void ScanToCloudData(const sensor::LidarScan& scan, const CloudLayout& layout,
                     std::vector<std::uint8_t>* data) {
  data->assign(static_cast<std::size_t>(layout.row_step) * layout.height, 0);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    std::uint8_t* p = data->data() + i * layout.point_step;
    for (const CloudField& f : layout.fields) {
      std::uint8_t* q = p + f.offset;
      if (f.name == "time") {
        std::memcpy(q, &scan.time[i], 8);
      } else if (f.name == "ring") {
        const std::uint16_t r = static_cast<std::uint16_t>(std::max(0, scan.ring[i]));
        std::memcpy(q, &r, 2);
      } else {
        const float v = f.name == "intensity" ? scan.intensity[i]
                                              : static_cast<float>(scan.points[i](f.name[0] - 'x'));
        std::memcpy(q, &v, 4);
      }
    }
  }
}

}  // namespace bag
}  // namespace plucker
