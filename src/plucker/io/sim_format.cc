#include "plucker/io/sim_format.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace plucker {
namespace io {

namespace fs = std::filesystem;
using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

constexpr char kHeader[] = "# plucker camera simulation";
constexpr double kMaxQuaternionNormError = 1e-9;

// ---------------------------------------------------------------------------------------------
// Writing.

class Writer {
 public:
  explicit Writer(std::string path) : path_(std::move(path)) {}
  Writer& Text(const std::string& s) {
    out_ += s;
    return *this;
  }
  // Numbers are separated by one space (none at the start of a line). %.17g reads back exactly.
  Writer& Num(double v) {
    if (!std::isfinite(v)) throw IoError(path_, "refusing to write a non-finite value");
    char buf[40];
    std::snprintf(buf, sizeof(buf), "%.17g", v);
    return Field(buf);
  }
  Writer& Int(long long v) { return Field(std::to_string(v)); }
  Writer& Vec(const Eigen::VectorXd& v) {
    for (int i = 0; i < v.size(); ++i) Num(v(i));
    return *this;
  }
  // TUM order: tx ty tz qx qy qz qw.
  Writer& Pose(const SE3d& T) {
    Vec(T.translation());
    return Vec(T.rotation().coeffs());
  }
  Writer& EndLine() {
    out_ += "\n";
    return *this;
  }
  Writer& Field(const std::string& text) {
    if (!out_.empty() && out_.back() != '\n') out_ += ' ';
    out_ += text;
    return *this;
  }
  void Commit() { WriteFileAtomically(path_, out_); }

 private:
  std::string path_;
  std::string out_;
};

std::string Join(const std::string& dir, const std::string& name) {
  return (fs::path(dir) / name).string();
}

// ---------------------------------------------------------------------------------------------
// Reading.

// The fields of one line: views into the parser's text.
class Fields {
 public:
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  std::string_view operator[](std::size_t i) const { return data_[i]; }
  std::string_view at(std::size_t i) const {
    if (i >= size_) throw std::out_of_range("Fields::at");
    return data_[i];
  }

 private:
  friend class FileParser;
  const std::string_view* data_ = nullptr;
  std::size_t size_ = 0;
};

struct Record {
  int line = 0;
  Fields fields;
};

// The records of a text file: one per line that is not empty or a comment, split at whitespace
// (the characters of isspace). The file is read at once and split in place (the fields are
// views into it; the observation files of a features folder have a million fields).
class FileParser {
 public:
  explicit FileParser(const std::string& path) : path_(path) {
    ReadText(path);
    const auto space = [](char c) {
      return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r';
    };
    const char* const text = text_.data();
    const std::size_t size = text_.size();
    // Sized first (no reallocation of a million fields): lines and fields counted.
    std::size_t lines = 1, fields = 0;
    for (std::size_t i = 0; i < size; ++i) {
      lines += text[i] == '\n';
      fields += !space(text[i]) && (i == 0 || space(text[i - 1]));
    }
    all_fields_.reserve(fields);
    records_.reserve(lines);
    std::vector<std::pair<std::size_t, std::size_t>> spans;  // per record: first field, count
    spans.reserve(lines);
    std::size_t pos = 0;
    int number = 0;
    while (pos < size) {
      const std::size_t eol = std::min(text_.find('\n', pos), size);
      ++number;
      if (number == 1) first_line_.assign(text + pos, eol - pos);
      const std::size_t first = all_fields_.size();
      for (std::size_t i = pos; i < eol;) {
        if (space(text[i])) {
          ++i;
          continue;
        }
        std::size_t j = i;
        while (j < eol && !space(text[j])) ++j;
        all_fields_.emplace_back(text + i, j - i);
        i = j;
      }
      pos = eol + 1;
      if (all_fields_.size() == first || all_fields_[first][0] == '#') {
        all_fields_.resize(first);
        continue;
      }
      Record r;
      r.line = number;
      records_.push_back(r);
      spans.emplace_back(first, all_fields_.size() - first);
    }
    for (std::size_t k = 0; k < records_.size(); ++k) {
      records_[k].fields.data_ = all_fields_.data() + spans[k].first;
      records_[k].fields.size_ = spans[k].second;
    }
    // The writer ends every line with '\n': a missing one means the file was cut short.
    if (!text_.empty() && text_.back() != '\n') {
      throw IoError(path + ":" + std::to_string(number),
                    "truncated file (the last line does not end with a newline)");
    }
  }
  FileParser(const FileParser&) = delete;
  FileParser& operator=(const FileParser&) = delete;

  // The whole file into text_ (one read of its size when it has one).
  void ReadText(const std::string& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw IoError(path, "cannot open (missing file?)");
    const std::streamoff size = in.tellg();
    in.seekg(0);
    if (size > 0 && in) {
      text_.resize(static_cast<std::size_t>(size));
      in.read(text_.data(), size);
      if (in.gcount() != size) throw IoError(path, "read error");
      return;
    }
    in.clear();
    std::ostringstream content;
    content << in.rdbuf();
    if (in.bad()) throw IoError(path, "read error");
    text_ = std::move(content).str();
  }

  const std::vector<Record>& records() const { return records_; }
  const std::string& first_line() const { return first_line_; }

  [[noreturn]] void Fail(const Record& r, const std::string& problem) const {
    throw IoError(path_ + ":" + std::to_string(r.line), problem);
  }
  void ExpectFields(const Record& r, std::size_t n, const std::string& what) const {
    if (r.fields.size() != n) {
      Fail(r, what + ": expected " + std::to_string(n) + " fields, found " +
                  std::to_string(r.fields.size()));
    }
  }
  // strtod and strtoll stop at the whitespace (or the text's terminating null) after a field.
  double Double(const Record& r, std::size_t i) const {
    const std::string_view f = r.fields.at(i);
    const char* begin = f.data();
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (end == begin || end != begin + f.size()) {
      Fail(r, "field " + std::to_string(i + 1) + " is not a number: '" + std::string(f) + "'");
    }
    if (!std::isfinite(v)) {
      Fail(r, "field " + std::to_string(i + 1) + " is not finite: '" + std::string(f) + "'");
    }
    return v;
  }
  long long Int(const Record& r, std::size_t i, long long lo, long long hi) const {
    const std::string_view f = r.fields.at(i);
    const char* begin = f.data();
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(begin, &end, 10);
    if (end == begin || end != begin + f.size() || errno == ERANGE) {
      Fail(r, "field " + std::to_string(i + 1) + " is not an integer: '" + std::string(f) + "'");
    }
    if (v < lo || v > hi) {
      Fail(r, "field " + std::to_string(i + 1) + " = " + std::string(f) + " is out of range [" +
                  std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return v;
  }
  Vector3d Vec3(const Record& r, std::size_t i) const {
    return Vector3d(Double(r, i), Double(r, i + 1), Double(r, i + 2));
  }
  // tx ty tz qx qy qz qw starting at field i.
  SE3d Pose(const Record& r, std::size_t i) const {
    const Vector3d t = Vec3(r, i);
    const Eigen::Quaterniond q(Double(r, i + 6), Double(r, i + 3), Double(r, i + 4),
                               Double(r, i + 5));
    if (!(std::abs(q.norm() - 1.0) <= kMaxQuaternionNormError)) {
      Fail(r, "the quaternion is not unit (norm " + std::to_string(q.norm()) + ")");
    }
    return SE3d(q, t);
  }

 private:
  std::string path_;
  std::string text_;
  std::string first_line_;
  std::vector<std::string_view> all_fields_;
  std::vector<Record> records_;
};

// Key-value files (scene.txt, rig.txt): the first field is the key.
void ReadScene(const std::string& path, sensor::CameraImuGroundTruth* scene) {
  const FileParser p(path);
  bool have_kind = false, have_free_space = false, have_counts = false;
  long long planes = 0, points = 0, segments = 0;
  for (const Record& r : p.records()) {
    const std::string_view key = r.fields[0];
    if (key == "counts") {
      p.ExpectFields(r, 4, "counts");
      planes = p.Int(r, 1, 0, LLONG_MAX);
      points = p.Int(r, 2, 0, LLONG_MAX);
      segments = p.Int(r, 3, 0, LLONG_MAX);
      have_counts = true;
    } else if (key == "kind") {
      p.ExpectFields(r, 2, "kind");
      scene->scene_kind = std::string(r.fields[1]);
      have_kind = true;
    } else if (key == "free_space") {
      p.ExpectFields(r, 7, "free_space");
      scene->free_space_w = Eigen::AlignedBox3d(p.Vec3(r, 1), p.Vec3(r, 4));
      if (scene->free_space_w.isEmpty()) p.Fail(r, "free_space: min > max");
      have_free_space = true;
    } else if (key == "plane") {
      p.ExpectFields(r, 6, "plane");
      p.Int(r, 1, static_cast<long long>(scene->planes_w.size()),
            static_cast<long long>(scene->planes_w.size()));
      const Eigen::Vector4d pi(p.Double(r, 2), p.Double(r, 3), p.Double(r, 4), p.Double(r, 5));
      if (!(std::abs(pi.head<3>().norm() - 1.0) <= 1e-9)) p.Fail(r, "plane normal is not unit");
      scene->planes_w.push_back(pi);
    } else if (key == "point") {
      p.ExpectFields(r, 6, "point");
      p.Int(r, 1, static_cast<long long>(scene->points_w.size()),
            static_cast<long long>(scene->points_w.size()));
      scene->points_w.push_back(p.Vec3(r, 2));
      scene->point_plane_ids.push_back(
          static_cast<int>(p.Int(r, 5, 0, static_cast<long long>(scene->planes_w.size()) - 1)));
    } else if (key == "segment") {
      p.ExpectFields(r, 8, "segment");
      p.Int(r, 1, static_cast<long long>(scene->segments_w.size()),
            static_cast<long long>(scene->segments_w.size()));
      LineSegment3 s{p.Vec3(r, 2), p.Vec3(r, 5)};
      if ((s.b_w - s.a_w).norm() == 0.0) p.Fail(r, "zero-length segment");
      scene->segments_w.push_back(s);
    } else {
      p.Fail(r, "unknown record '" + std::string(key) + "'");
    }
  }
  if (!have_kind) throw IoError(path, "missing 'kind' record");
  if (!have_free_space) throw IoError(path, "missing 'free_space' record");
  if (!have_counts) throw IoError(path, "missing 'counts' record");
  if (static_cast<long long>(scene->planes_w.size()) != planes ||
      static_cast<long long>(scene->points_w.size()) != points ||
      static_cast<long long>(scene->segments_w.size()) != segments) {
    throw IoError(path,
                  "the numbers of planes, points and segments differ from its 'counts' "
                  "record (truncated or edited file?)");
  }
}

// Row counts announced by rig.txt, checked against the other files (catches files cut at a
// line boundary).
struct Counts {
  long long frames = 0, imu = 0, points = 0, segments = 0;
  long long cam1_points = -1, cam1_segments = -1;  // -1: no second camera
};

void CheckCount(const std::string& path, std::size_t found, long long expected) {
  if (static_cast<long long>(found) != expected) {
    throw IoError(path, "has " + std::to_string(found) + " data rows, rig.txt announces " +
                            std::to_string(expected) + " (truncated or edited file?)");
  }
}

// The fisheye records of rig.txt (docs/sim-format.md): `equidistant k1 k2 k3 k4` and
// `view fx fy cx cy W H POINTS_IN_VIEW`, both or neither.
void ReadFisheye(const FileParser& p, const std::string& path,
                 std::map<std::string, const Record*>& by_key, sensor::CameraRig* rig) {
  const bool has_equidistant = by_key.count("equidistant") > 0, has_view = by_key.count("view") > 0;
  if (has_equidistant != has_view) {
    throw IoError(path, std::string("missing '") + (has_view ? "equidistant" : "view") +
                            "' record (a fisheye rig needs both)");
  }
  if (!has_equidistant) return;
  sensor::FisheyeView& f = rig->fisheye.emplace();
  const Record& e = *by_key["equidistant"];
  f.coeffs = EquidistantDistortion{p.Double(e, 1), p.Double(e, 2), p.Double(e, 3), p.Double(e, 4)};
  const Record& v = *by_key["view"];
  f.view_K = PinholeIntrinsics{p.Double(v, 1), p.Double(v, 2), p.Double(v, 3), p.Double(v, 4)};
  if (!f.view_K.IsValid()) p.Fail(v, "view: fx and fy must be positive");
  f.view_width = static_cast<int>(p.Int(v, 5, 2, 1 << 20));
  f.view_height = static_cast<int>(p.Int(v, 6, 2, 1 << 20));
  f.points_in_view = p.Int(v, 7, 0, 1) == 1;
}

void ReadRig(const std::string& path, sensor::CameraImuSequence* sequence, Counts* counts) {
  const FileParser p(path);
  if (p.first_line().rfind(kHeader, 0) != 0) {
    throw IoError(path + ":1", std::string("missing header line '") + kHeader + "'");
  }
  std::map<std::string, const Record*> by_key;
  for (const Record& r : p.records()) {
    if (!by_key.emplace(r.fields[0], &r).second) {
      p.Fail(r, "duplicate '" + std::string(r.fields[0]) + "'");
    }
  }
  const std::map<std::string, std::size_t> expected = {
      {"image", 3},         {"intrinsics", 5},       {"T_b_c", 8},       {"imu_rate_hz", 2},
      {"imu_noise", 5},     {"imu_initial_bias", 7}, {"gravity", 4},     {"pixel_sigma", 2},
      {"outlier_ratio", 2}, {"min_segment_px", 2},   {"depth_range", 3}, {"observe", 3},
      {"counts", 5},        {"equidistant", 5},      {"view", 8},        {"T_c0_c1", 8},
      {"cam1_counts", 3}};
  for (const auto& [key, record] : by_key) {
    const auto it = expected.find(key);
    if (it == expected.end()) p.Fail(*record, "unknown record '" + key + "'");
    p.ExpectFields(*record, it->second, key);
  }
  for (const auto& [key, n] : expected) {
    (void)n;
    // The initial biases are ground truth: a folder without it may leave them out.
    // The fisheye records: both or neither (checked below).
    const bool optional = (key == "imu_initial_bias" && !sequence->ground_truth) ||
                          key == "equidistant" || key == "view" || key == "T_c0_c1" ||
                          key == "cam1_counts";
    if (!optional && !by_key.count(key)) throw IoError(path, "missing '" + key + "' record");
  }
  sensor::CameraRig& rig = sequence->rig;
  const Record& image = *by_key["image"];
  rig.width = static_cast<int>(p.Int(image, 1, 2, 1 << 20));
  rig.height = static_cast<int>(p.Int(image, 2, 2, 1 << 20));
  const Record& k = *by_key["intrinsics"];
  rig.K = PinholeIntrinsics{p.Double(k, 1), p.Double(k, 2), p.Double(k, 3), p.Double(k, 4)};
  if (!rig.K.IsValid()) p.Fail(k, "intrinsics: fx and fy must be positive");
  const Record& tbc = *by_key["T_b_c"];
  rig.T_b_c = p.Pose(tbc, 1);
  ReadFisheye(p, path, by_key, &rig);

  sensor::ImuModel& imu = sequence->imu_model;
  const Record& rate = *by_key["imu_rate_hz"];
  imu.rate_hz = p.Double(rate, 1);
  if (!(imu.rate_hz > 0)) p.Fail(rate, "imu_rate_hz must be positive");
  const Record& noise = *by_key["imu_noise"];
  imu.gyro_noise_density = p.Double(noise, 1);
  imu.accel_noise_density = p.Double(noise, 2);
  imu.gyro_bias_random_walk = p.Double(noise, 3);
  imu.accel_bias_random_walk = p.Double(noise, 4);
  for (int i = 1; i <= 4; ++i) {
    if (p.Double(noise, i) < 0) p.Fail(noise, "imu_noise: densities must be >= 0");
  }
  if (sequence->ground_truth && by_key.count("imu_initial_bias")) {
    const Record& bias = *by_key["imu_initial_bias"];
    sequence->ground_truth->initial_gyro_bias = p.Vec3(bias, 1);
    sequence->ground_truth->initial_accel_bias = p.Vec3(bias, 4);
  }
  sequence->gravity_w = p.Vec3(*by_key["gravity"], 1);

  sensor::ObservationModel& obs = sequence->observation_model;
  const Record& sigma = *by_key["pixel_sigma"];
  obs.pixel_sigma = p.Double(sigma, 1);
  if (obs.pixel_sigma < 0) p.Fail(sigma, "pixel_sigma must be >= 0");
  const Record& ratio = *by_key["outlier_ratio"];
  obs.outlier_ratio = p.Double(ratio, 1);
  if (obs.outlier_ratio < 0 || obs.outlier_ratio > 0.9)
    p.Fail(ratio, "outlier_ratio not in [0, 0.9]");
  const Record& min_px = *by_key["min_segment_px"];
  obs.min_segment_px = p.Double(min_px, 1);
  if (obs.min_segment_px < 0) p.Fail(min_px, "min_segment_px must be >= 0");
  const Record& depth = *by_key["depth_range"];
  obs.min_depth = p.Double(depth, 1);
  obs.max_depth = p.Double(depth, 2);
  if (!(obs.min_depth > 0 && obs.max_depth > obs.min_depth)) {
    p.Fail(depth, "depth_range: need 0 < min < max");
  }
  const Record& observe = *by_key["observe"];
  obs.observe_points = p.Int(observe, 1, 0, 1) == 1;
  obs.observe_segments = p.Int(observe, 2, 0, 1) == 1;
  const Record& c = *by_key["counts"];
  counts->frames = p.Int(c, 1, 1, LLONG_MAX);
  counts->imu = p.Int(c, 2, 0, LLONG_MAX);
  counts->points = p.Int(c, 3, 0, LLONG_MAX);
  counts->segments = p.Int(c, 4, 0, LLONG_MAX);
  // A stereo rig's second camera: T_c0_c1 and cam1_counts, both or neither.
  const bool has_T = by_key.count("T_c0_c1") > 0, has_counts = by_key.count("cam1_counts") > 0;
  if (has_T != has_counts) {
    throw IoError(path, std::string("missing '") + (has_T ? "cam1_counts" : "T_c0_c1") +
                            "' record (a second camera needs both)");
  }
  if (!has_T) return;
  sequence->cam1.emplace().T_c0_c1 = p.Pose(*by_key["T_c0_c1"], 1);
  const Record& c1 = *by_key["cam1_counts"];
  counts->cam1_points = p.Int(c1, 1, 0, LLONG_MAX);
  counts->cam1_segments = p.Int(c1, 2, 0, LLONG_MAX);
}

// frames.txt: one time a row, one row a frame.
void ReadFrameTimes(const std::string& path, std::vector<double>* frame_times) {
  const FileParser p(path);
  for (const Record& r : p.records()) {
    p.ExpectFields(r, 1, "frame time (t)");
    const double t = p.Double(r, 0);
    if (!frame_times->empty() && !(t > frame_times->back())) p.Fail(r, "frame times must increase");
    frame_times->push_back(t);
  }
  if (frame_times->empty()) throw IoError(path, "no frames");
}

// trajectory.txt and body_states.txt, one row a frame at the times of frames.txt (folders
// written before frames.txt existed: the times of trajectory.txt).
void ReadGroundTruthFrames(const std::string& trajectory_path, const std::string& body_path,
                           sensor::CameraImuSequence* sequence) {
  std::vector<double>& frame_times = sequence->frame_times;
  sensor::CameraImuGroundTruth& gt = sequence->ground_truth.value();
  if (frame_times.empty()) {
    const FileParser tp(trajectory_path);
    for (const Record& r : tp.records()) {
      if (!frame_times.empty() && !(tp.Double(r, 0) > frame_times.back())) {
        tp.Fail(r, "frame times must increase");
      }
      frame_times.push_back(tp.Double(r, 0));
    }
    if (frame_times.empty()) throw IoError(trajectory_path, "no frames");
  }
  auto check_time = [&](const FileParser& p, const Record& r, std::size_t i) {
    if (i >= frame_times.size()) p.Fail(r, "more rows than frames.txt has frames");
    if (p.Double(r, 0) != frame_times[i]) {
      p.Fail(r, "time differs from frames.txt row " + std::to_string(i + 1));
    }
  };
  const FileParser tp(trajectory_path);
  for (const Record& r : tp.records()) {
    tp.ExpectFields(r, 8, "trajectory row (t tx ty tz qx qy qz qw)");
    check_time(tp, r, gt.T_w_c.size());
    gt.T_w_c.push_back(tp.Pose(r, 1));
  }
  const FileParser bp(body_path);
  for (const Record& r : bp.records()) {
    bp.ExpectFields(r, 11, "body state row (t tx ty tz qx qy qz qw vx vy vz)");
    check_time(bp, r, gt.T_w_b.size());
    gt.T_w_b.push_back(bp.Pose(r, 1));
    gt.v_w.push_back(bp.Vec3(r, 8));
  }
  for (const auto& [path, rows] :
       {std::pair{trajectory_path, gt.T_w_c.size()}, std::pair{body_path, gt.T_w_b.size()}}) {
    if (rows != frame_times.size()) {
      throw IoError(path, "has " + std::to_string(rows) + " rows, frames.txt has " +
                              std::to_string(frame_times.size()));
    }
  }
}

void ReadImu(const std::string& path, std::vector<sensor::ImuSample>* imu) {
  const FileParser p(path);
  imu->reserve(imu->size() + p.records().size());
  bool biases = false;  // the bias columns are ground truth: all rows have them or none
  for (const Record& r : p.records()) {
    if (imu->empty()) biases = r.fields.size() == 13;
    p.ExpectFields(
        r, biases ? 13 : 7,
        biases ? "imu row (t gyro accel gyro_bias accel_bias)" : "imu row (t gyro accel)");
    sensor::ImuSample s;
    s.t = p.Double(r, 0);
    if (!imu->empty() && !(s.t > imu->back().t)) p.Fail(r, "imu times must increase");
    s.gyro = p.Vec3(r, 1);
    s.accel = p.Vec3(r, 4);
    if (biases) {
      s.gyro_bias = p.Vec3(r, 7);
      s.accel_bias = p.Vec3(r, 10);
    }
    imu->push_back(s);
  }
}

void ReadObservations(const std::string& points_path, const std::string& segments_path,
                      sensor::CameraImuSequence* sequence) {
  const long long last_frame = static_cast<long long>(sequence->frame_times.size()) - 1;
  // With a scene, ids index its points and segments; without, they are any track ids.
  const auto& gt = sequence->ground_truth;
  const long long max_point_id = gt ? static_cast<long long>(gt->points_w.size()) - 1 : INT_MAX;
  const long long max_line_id = gt ? static_cast<long long>(gt->segments_w.size()) - 1 : INT_MAX;
  std::vector<sensor::PointObservation>& points = sequence->points;
  std::vector<sensor::SegmentObservation>& segments = sequence->segments;
  const FileParser pp(points_path);
  points.reserve(points.size() + pp.records().size());
  for (const Record& r : pp.records()) {
    pp.ExpectFields(r, 4, "point observation (frame point_id u v)");
    sensor::PointObservation o;
    o.frame = static_cast<int>(pp.Int(r, 0, 0, last_frame));
    o.point_id = static_cast<int>(pp.Int(r, 1, -1, max_point_id));
    o.uv = Vector2d(pp.Double(r, 2), pp.Double(r, 3));
    if (!points.empty() && o.frame < points.back().frame) {
      pp.Fail(r, "observations must be sorted by frame");
    }
    points.push_back(o);
  }
  const FileParser sp(segments_path);
  segments.reserve(segments.size() + sp.records().size());
  for (const Record& r : sp.records()) {
    sp.ExpectFields(r, 6, "segment observation (frame line_id su sv eu ev)");
    sensor::SegmentObservation o;
    o.frame = static_cast<int>(sp.Int(r, 0, 0, last_frame));
    o.line_id = static_cast<int>(sp.Int(r, 1, -1, max_line_id));
    o.s_px = Vector2d(sp.Double(r, 2), sp.Double(r, 3));
    o.e_px = Vector2d(sp.Double(r, 4), sp.Double(r, 5));
    if (!segments.empty() && o.frame < segments.back().frame) {
      sp.Fail(r, "observations must be sorted by frame");
    }
    segments.push_back(o);
  }
}

// ---------------------------------------------------------------------------------------------
// Writing the folder, file by file.

void CheckWritable(const std::string& dir, const sensor::CameraImuSequence& sequence) {
  const std::size_t n = sequence.frame_times.size();
  if (n == 0) throw IoError(dir, "the sequence has no frames");
  if (!sequence.ground_truth) return;
  const sensor::CameraImuGroundTruth& gt = *sequence.ground_truth;
  if (gt.T_w_c.size() != n || gt.T_w_b.size() != n || gt.v_w.size() != n) {
    throw IoError(dir,
                  "inconsistent sequence: frame_times and the ground truth T_w_c, T_w_b and v_w "
                  "differ in size");
  }
  if (gt.point_plane_ids.size() != gt.points_w.size()) {
    throw IoError(dir, "inconsistent sequence: point_plane_ids and points_w differ in size");
  }
  if (gt.scene_kind.empty() || gt.scene_kind.find_first_of(" \t\n\r#") != std::string::npos) {
    throw IoError(dir, "the scene kind must be one word: '" + gt.scene_kind + "'");
  }
}

void WriteRig(const std::string& path, const std::string& header,
              const sensor::CameraImuSequence& sequence) {
  Writer w(path);
  const sensor::CameraRig& rig = sequence.rig;
  const sensor::ImuModel& imu = sequence.imu_model;
  const sensor::ObservationModel& obs = sequence.observation_model;
  w.Text(header).Text("# camera rig, IMU and observation noise models\n");
  w.Text("image").Int(rig.width).Int(rig.height).EndLine();
  w.Text("intrinsics").Num(rig.K.fx).Num(rig.K.fy).Num(rig.K.cx).Num(rig.K.cy).EndLine();
  w.Text("T_b_c").Pose(rig.T_b_c).EndLine();
  if (const auto& f = rig.fisheye) {
    const EquidistantDistortion& d = f->coeffs;
    w.Text("equidistant").Num(d.k1).Num(d.k2).Num(d.k3).Num(d.k4).EndLine();
    w.Text("view").Num(f->view_K.fx).Num(f->view_K.fy).Num(f->view_K.cx).Num(f->view_K.cy);
    w.Int(f->view_width).Int(f->view_height).Int(f->points_in_view).EndLine();
  }
  w.Text("imu_rate_hz").Num(imu.rate_hz).EndLine();
  w.Text("imu_noise").Num(imu.gyro_noise_density).Num(imu.accel_noise_density);
  w.Num(imu.gyro_bias_random_walk).Num(imu.accel_bias_random_walk).EndLine();
  if (const auto& gt = sequence.ground_truth) {
    w.Text("imu_initial_bias").Vec(gt->initial_gyro_bias).Vec(gt->initial_accel_bias).EndLine();
  }
  w.Text("gravity").Vec(sequence.gravity_w).EndLine();
  w.Text("pixel_sigma").Num(obs.pixel_sigma).EndLine();
  w.Text("outlier_ratio").Num(obs.outlier_ratio).EndLine();
  w.Text("min_segment_px").Num(obs.min_segment_px).EndLine();
  w.Text("depth_range").Num(obs.min_depth).Num(obs.max_depth).EndLine();
  w.Text("observe").Int(obs.observe_points).Int(obs.observe_segments).EndLine();
  w.Text("counts").Int(static_cast<long long>(sequence.frame_times.size()));
  w.Int(static_cast<long long>(sequence.imu.size()));
  w.Int(static_cast<long long>(sequence.points.size()));
  w.Int(static_cast<long long>(sequence.segments.size())).EndLine();
  if (const auto& cam1 = sequence.cam1) {
    w.Text("T_c0_c1").Pose(cam1->T_c0_c1).EndLine();
    w.Text("cam1_counts").Int(static_cast<long long>(cam1->points.size()));
    w.Int(static_cast<long long>(cam1->segments.size())).EndLine();
  }
  w.Commit();
}

void WriteScene(const std::string& path, const std::string& header,
                const sensor::CameraImuGroundTruth& s) {
  Writer w(path);
  w.Text(header).Text("# kind K | free_space min max | plane id mx my mz e | ");
  w.Text("point id x y z plane_id | segment id ax ay az bx by bz\n");
  w.Text("kind " + s.scene_kind).EndLine();
  w.Text("counts").Int(static_cast<long long>(s.planes_w.size()));
  w.Int(static_cast<long long>(s.points_w.size()));
  w.Int(static_cast<long long>(s.segments_w.size())).EndLine();
  w.Text("free_space").Vec(s.free_space_w.min()).Vec(s.free_space_w.max()).EndLine();
  for (std::size_t i = 0; i < s.planes_w.size(); ++i) {
    w.Text("plane").Int(static_cast<long long>(i)).Vec(s.planes_w[i]).EndLine();
  }
  for (std::size_t i = 0; i < s.points_w.size(); ++i) {
    w.Text("point").Int(static_cast<long long>(i)).Vec(s.points_w[i]);
    w.Int(s.point_plane_ids[i]).EndLine();
  }
  for (std::size_t i = 0; i < s.segments_w.size(); ++i) {
    w.Text("segment").Int(static_cast<long long>(i)).Vec(s.segments_w[i].a_w);
    w.Vec(s.segments_w[i].b_w).EndLine();
  }
  w.Commit();
}

void WriteGroundTruth(const std::string& dir, const std::string& header,
                      const sensor::CameraImuSequence& sequence) {
  const sensor::CameraImuGroundTruth& gt = *sequence.ground_truth;
  WriteScene(Join(dir, "scene.txt"), header, gt);
  Writer traj(Join(dir, "trajectory.txt"));
  traj.Text(header).Text("# T_w_c per frame (TUM): t tx ty tz qx qy qz qw\n");
  Writer body(Join(dir, "body_states.txt"));
  body.Text(header).Text("# T_w_b and v_w per frame: t tx ty tz qx qy qz qw vx vy vz\n");
  for (std::size_t i = 0; i < sequence.frame_times.size(); ++i) {
    traj.Num(sequence.frame_times[i]).Pose(gt.T_w_c[i]).EndLine();
    body.Num(sequence.frame_times[i]).Pose(gt.T_w_b[i]).Vec(gt.v_w[i]).EndLine();
  }
  traj.Commit();
  body.Commit();
}

// The bias columns are ground truth: written with it, left out without.
void WriteImu(const std::string& path, const std::string& header,
              const sensor::CameraImuSequence& sequence) {
  const bool biases = sequence.ground_truth.has_value();
  Writer w(path);
  w.Text(header).Text(biases
                          ? "# t gx gy gz ax ay az bgx bgy bgz bax bay baz (biases: ground truth)\n"
                          : "# t gx gy gz ax ay az\n");
  for (const sensor::ImuSample& s : sequence.imu) {
    w.Num(s.t).Vec(s.gyro).Vec(s.accel);
    if (biases) w.Vec(s.gyro_bias).Vec(s.accel_bias);
    w.EndLine();
  }
  w.Commit();
}

void WriteObservations(const std::string& dir, const std::string& header,
                       const std::vector<sensor::PointObservation>& points,
                       const std::vector<sensor::SegmentObservation>& segments,
                       const std::string& prefix = "") {
  Writer p(Join(dir, prefix + "points.txt"));
  p.Text(header).Text("# frame point_id u v (point_id -1: outlier)\n");
  for (const sensor::PointObservation& o : points) {
    p.Int(o.frame).Int(o.point_id).Vec(o.uv).EndLine();
  }
  p.Commit();
  Writer s(Join(dir, prefix + "segments.txt"));
  s.Text(header).Text("# frame line_id su sv eu ev (line_id -1: outlier)\n");
  for (const sensor::SegmentObservation& o : segments) {
    s.Int(o.frame).Int(o.line_id).Vec(o.s_px).Vec(o.e_px).EndLine();
  }
  s.Commit();
}

}  // namespace

const std::vector<std::string>& CameraImuSequenceFileNames() {
  static const std::vector<std::string> names = {
      "rig.txt", "frames.txt", "scene.txt",    "trajectory.txt",  "body_states.txt",
      "imu.txt", "points.txt", "segments.txt", "cam1_points.txt", "cam1_segments.txt"};
  return names;
}

void WriteCameraImuSequence(const std::string& dir, const sensor::CameraImuSequence& sequence) {
  CheckWritable(dir, sequence);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError(dir, "cannot create the folder: " + ec.message());
  // rig.txt first: its header marks the folder as a simulation (IsSafeToWriteCameraImuSequence).
  const std::string header = std::string(kHeader) + " (docs/sim-format.md), format 1\n";
  WriteRig(Join(dir, "rig.txt"), header, sequence);
  {
    Writer w(Join(dir, "frames.txt"));
    w.Text(header).Text("# t: the time of each frame\n");
    for (double t : sequence.frame_times) w.Num(t).EndLine();
    w.Commit();
  }
  if (sequence.ground_truth) {
    WriteGroundTruth(dir, header, sequence);
  } else {
    // A previous sequence's ground truth would be read as this one's.
    for (const char* name : {"scene.txt", "trajectory.txt", "body_states.txt"}) {
      fs::remove(Join(dir, name), ec);
    }
  }
  WriteImu(Join(dir, "imu.txt"), header, sequence);
  WriteObservations(dir, header, sequence.points, sequence.segments);
  if (sequence.cam1) {
    WriteObservations(dir, header, sequence.cam1->points, sequence.cam1->segments, "cam1_");
  } else {
    // A previous sequence's second camera would be read as this one's.
    for (const char* name : {"cam1_points.txt", "cam1_segments.txt"}) {
      fs::remove(Join(dir, name), ec);
    }
  }
}

sensor::CameraImuSequence ReadCameraImuSequence(const std::string& dir) {
  sensor::CameraImuSequence sequence;
  const std::vector<std::string> truth = {"scene.txt", "trajectory.txt", "body_states.txt"};
  std::vector<std::string> missing_truth;
  for (const std::string& name : truth) {
    if (!fs::exists(Join(dir, name))) missing_truth.push_back(name);
  }
  if (missing_truth.size() != 0 && missing_truth.size() != truth.size()) {
    throw IoError(Join(dir, missing_truth[0]),
                  "missing: the ground truth is scene.txt, trajectory.txt and body_states.txt "
                  "together (or none of them)");
  }
  if (missing_truth.empty()) sequence.ground_truth.emplace();
  Counts counts;
  ReadRig(Join(dir, "rig.txt"), &sequence, &counts);
  // Frame times: frames.txt, or trajectory.txt in folders written before frames.txt existed.
  const bool have_frames = !sequence.ground_truth || fs::exists(Join(dir, "frames.txt"));
  const std::string frames = Join(dir, have_frames ? "frames.txt" : "trajectory.txt");
  if (have_frames) ReadFrameTimes(frames, &sequence.frame_times);
  if (sequence.ground_truth) {
    ReadScene(Join(dir, "scene.txt"), &*sequence.ground_truth);
    ReadGroundTruthFrames(Join(dir, "trajectory.txt"), Join(dir, "body_states.txt"), &sequence);
  }
  CheckCount(frames, sequence.frame_times.size(), counts.frames);
  ReadImu(Join(dir, "imu.txt"), &sequence.imu);
  CheckCount(Join(dir, "imu.txt"), sequence.imu.size(), counts.imu);
  ReadObservations(Join(dir, "points.txt"), Join(dir, "segments.txt"), &sequence);
  CheckCount(Join(dir, "points.txt"), sequence.points.size(), counts.points);
  CheckCount(Join(dir, "segments.txt"), sequence.segments.size(), counts.segments);
  if (sequence.cam1) {
    // The same validation as cam0's, into cam1 (ReadObservations appends to the sequence's).
    std::swap(sequence.points, sequence.cam1->points);
    std::swap(sequence.segments, sequence.cam1->segments);
    ReadObservations(Join(dir, "cam1_points.txt"), Join(dir, "cam1_segments.txt"), &sequence);
    std::swap(sequence.points, sequence.cam1->points);
    std::swap(sequence.segments, sequence.cam1->segments);
    CheckCount(Join(dir, "cam1_points.txt"), sequence.cam1->points.size(), counts.cam1_points);
    CheckCount(Join(dir, "cam1_segments.txt"), sequence.cam1->segments.size(),
               counts.cam1_segments);
  }
  return sequence;
}

bool IsSafeToWriteCameraImuSequence(const std::string& dir, std::string* why) {
  auto refuse = [why](const std::string& reason) {
    if (why) *why = reason;
    return false;
  };
  std::error_code ec;
  if (!fs::exists(dir, ec)) return true;
  if (!fs::is_directory(dir, ec)) return refuse(dir + " exists and is not a folder");
  const std::vector<std::string>& names = CameraImuSequenceFileNames();
  const std::set<std::string> known(names.begin(), names.end());
  bool any = false;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    any = true;
    const std::string name = it->path().filename().string();
    const std::string suffix = ".tmp-plucker";  // left behind by an interrupted atomic write
    const bool temp = name.size() > suffix.size() &&
                      name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
    if (!it->is_regular_file() || (!known.count(name) && !temp)) {
      return refuse(Join(dir, name) + " is not part of a camera simulation");
    }
  }
  if (ec) return refuse(dir + ": cannot list the folder: " + ec.message());
  if (!any) return true;
  std::ifstream rig(Join(dir, "rig.txt"));
  std::string first;
  if (!rig || !std::getline(rig, first) || first.rfind(kHeader, 0) != 0) {
    return refuse(Join(dir, "rig.txt") + " is missing or lacks the simulation header");
  }
  return true;
}

}  // namespace io
}  // namespace plucker
