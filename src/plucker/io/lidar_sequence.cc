#include "plucker/io/lidar_sequence.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <system_error>

#include "plucker/io/kitti_lidar.h"
#include "plucker/io/pcd.h"

namespace plucker {
namespace io {
namespace {

namespace fs = std::filesystem;

bool IsDir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}
bool IsFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

// Files in `dir` with extension `ext` (e.g. ".bin"), not recursive. Throws IoError.
std::vector<fs::path> ListFiles(const fs::path& dir, const std::string& ext) {
  std::vector<fs::path> files;
  std::error_code ec;
  fs::directory_iterator it(dir, ec), end;
  if (ec) throw IoError(dir.string(), "cannot read folder: " + ec.message());
  for (; it != end; it.increment(ec)) {
    if (ec) throw IoError(dir.string(), "cannot read folder: " + ec.message());
    if (it->path().extension() == ext && IsFile(it->path())) files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

bool AllDigits(const std::string& s) {
  return !s.empty() && s.size() <= 12 && s.find_first_not_of("0123456789") == std::string::npos;
}

bool ParseStemNumber(const std::string& s, double* v) {
  if (s.empty()) return false;
  char* end = nullptr;
  *v = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(*v);
}

}  // namespace

LidarSequence LidarSequence::Open(const std::string& dir, const std::string& sequence) {
  fs::path base(dir);
  if (!fs::exists(base)) throw IoError(dir, "no such folder");
  if (!IsDir(base)) throw IoError(dir, "not a folder");
  if (!sequence.empty()) {
    const fs::path seq_dir = base / "sequences" / sequence;
    if (IsDir(seq_dir)) {
      base = seq_dir;
    } else if (IsDir(base / sequence)) {
      base = base / sequence;
    } else {
      throw IoError(dir, "no sequence '" + sequence + "' (looked for sequences/" + sequence +
                             " and " + sequence + ")");
    }
  }

  LidarSequence seq;
  fs::path frame_dir;
  std::string ext;
  fs::path root = base;
  if (IsDir(base / "pcd") && !ListFiles(base / "pcd", ".pcd").empty()) {
    frame_dir = base / "pcd", ext = ".pcd", seq.format_ = Format::kPcd;
  } else if (IsDir(base / "velodyne")) {
    frame_dir = base / "velodyne", ext = ".bin", seq.format_ = Format::kKittiBin;
  } else if (!ListFiles(base, ".pcd").empty()) {
    frame_dir = base, ext = ".pcd", seq.format_ = Format::kPcd;
  } else if (!ListFiles(base, ".bin").empty()) {
    frame_dir = base, ext = ".bin", seq.format_ = Format::kKittiBin;
    if (base.filename() == "velodyne" && base.has_parent_path()) root = base.parent_path();
  } else if (IsDir(base / "sequences")) {
    throw IoError(dir, "looks like a KITTI dataset root: choose a sequence (e.g. --sequence 00)");
  } else {
    throw IoError(base.string(),
                  "no LiDAR frames found (expected velodyne/*.bin, pcd/*.pcd or "
                  "*.pcd files)");
  }
  seq.root_ = root.string();

  const std::vector<fs::path> files = ListFiles(frame_dir, ext);
  if (files.empty()) throw IoError(frame_dir.string(), "no " + ext + " files");

  bool numbered = true;
  for (const fs::path& f : files) numbered = numbered && AllDigits(f.stem().string());
  std::vector<double> name_times;
  if (numbered) {
    std::map<std::size_t, fs::path> by_number;
    for (const fs::path& f : files) by_number[std::stoull(f.stem().string())] = f;
    const std::size_t first = by_number.begin()->first, last = by_number.rbegin()->first;
    if (last - first > 100000000) throw IoError(frame_dir.string(), "frame numbers too sparse");
    const std::size_t width = files.front().stem().string().size();
    for (std::size_t k = first; k <= last; ++k) {
      LidarFrameRef ref;
      ref.index = k;
      auto it = by_number.find(k);
      if (it != by_number.end()) {
        ref.path = it->second.string();
      } else {
        std::string num = std::to_string(k);
        if (num.size() < width) num.insert(0, width - num.size(), '0');
        ref.path = (frame_dir / (num + ext)).string();
        ref.missing = true;
      }
      seq.frames_.push_back(ref);
    }
  } else {
    std::vector<std::pair<double, fs::path>> stamped;
    bool all_stamped = true;
    for (const fs::path& f : files) {
      double v;
      all_stamped = all_stamped && ParseStemNumber(f.stem().string(), &v);
      stamped.emplace_back(all_stamped ? v : 0.0, f);
    }
    if (all_stamped)
      std::stable_sort(stamped.begin(), stamped.end(),
                       [](const auto& a, const auto& b) { return a.first < b.first; });
    for (std::size_t k = 0; k < stamped.size(); ++k) {
      LidarFrameRef ref;
      ref.index = k;
      ref.path = stamped[k].second.string();
      seq.frames_.push_back(ref);
      if (all_stamped) name_times.push_back(stamped[k].first);
    }
  }

  const fs::path calib = root / "calib.txt";
  if (IsFile(calib)) {
    seq.has_calib_ = true;
    seq.T_cam0_velo_ = ReadKittiCalibTr(calib.string());
  }
  const fs::path times = root / "times.txt";
  if (IsFile(times)) {
    const std::vector<double> t = ReadKittiTimes(times.string());
    const std::size_t need = numbered ? seq.frames_.back().index + 1 : seq.frames_.size();
    if (t.size() < need) {
      throw IoError(times.string(), "has " + std::to_string(t.size()) + " times for " +
                                        std::to_string(need) + " frames");
    }
    for (const LidarFrameRef& f : seq.frames_) seq.times_.push_back(t[numbered ? f.index : 0]);
    if (!numbered) seq.times_.assign(t.begin(), t.begin() + seq.frames_.size());
  } else {
    seq.times_ = name_times;
  }

  if (seq.format_ == Format::kPcd) {
    for (const LidarFrameRef& f : seq.frames_) {
      if (f.missing) continue;
      try {
        seq.has_point_time_ = ReadPcdHeader(f.path).has_time();
      } catch (const IoError&) {
        continue;  // reported when the frame is read
      }
      break;
    }
  }
  return seq;
}

std::size_t LidarSequence::num_missing() const {
  return static_cast<std::size_t>(std::count_if(frames_.begin(), frames_.end(),
                                                [](const LidarFrameRef& f) { return f.missing; }));
}

bool LidarSequence::Read(std::size_t i, LidarScan* scan, std::string* error,
                         ScanReadStats* stats) const {
  if (i >= frames_.size()) {
    if (error) *error = root_ + ": frame " + std::to_string(i) + " out of range";
    return false;
  }
  const LidarFrameRef& f = frames_[i];
  if (f.missing) {
    if (error) *error = f.path + ": missing frame (gap in the numbering)";
    return false;
  }
  try {
    ReadFileInto(f.path, &read_buffer_);
    if (format_ == Format::kPcd)
      ParsePcd(read_buffer_, f.path, scan, stats);
    else
      ParseKittiBin(read_buffer_, f.path, scan, stats);
  } catch (const std::exception& e) {  // IoError, or bad_alloc on a corrupt header
    if (error) *error = e.what();
    return false;
  }
  if (!times_.empty()) scan->timestamp = times_[i];
  return true;
}

std::string LidarSequence::description() const {
  std::string d = format_ == Format::kPcd ? "PCD sequence at " : "KITTI sequence at ";
  d += root_ + ", " + std::to_string(frames_.size()) + " frames";
  const std::size_t missing = num_missing();
  if (missing) d += " (" + std::to_string(missing) + " missing)";
  if (has_calib_) d += T_cam0_velo_ ? ", calib Tr" : ", calib.txt without Tr";
  if (!times_.empty()) d += ", times";
  if (has_point_time_) d += ", per-point time";
  return d;
}

}  // namespace io
}  // namespace plucker
