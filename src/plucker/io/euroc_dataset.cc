#include "plucker/io/euroc_dataset.h"
#include "plucker/geometry/median.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "plucker/io/io_error.h"
#include "plucker/io/kitti_lidar.h"

namespace plucker {
namespace io {

namespace {

namespace fs = std::filesystem;

std::string Seconds(double t) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.3f s", t);
  return buf;
}

std::string Trim(const std::string& s) {
  const std::size_t a = s.find_first_not_of(" \t\r");
  const std::size_t b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

struct Interval {
  double begin, end;
};

// Steps between IMU samples longer than options.max_imu_gap_s.
std::vector<Interval> ImuGaps(const std::vector<sensor::ImuSample>& imu, double max_gap_s) {
  std::vector<Interval> gaps;
  for (std::size_t i = 1; i < imu.size(); ++i) {
    if (imu[i].t - imu[i - 1].t > max_gap_s) gaps.push_back({imu[i - 1].t, imu[i].t});
  }
  return gaps;
}

// Why the IMU does not cover time t, or "" when it does.
std::string CoverageProblem(const std::vector<sensor::ImuSample>& imu,
                            const std::vector<Interval>& gaps, double t) {
  if (t < imu.front().t) return "no IMU coverage (before the first IMU sample)";
  if (t > imu.back().t) return "no IMU coverage (after the last IMU sample)";
  for (const Interval& g : gaps) {
    if (t > g.begin && t < g.end)
      return "no IMU coverage (inside a gap of " + Seconds(g.end - g.begin) + ")";
  }
  return "";
}

void WarnDroppedFrames(const std::vector<EurocFrame>& frames, double factor,
                       const std::string& camera_name, std::vector<std::string>* warnings) {
  if (frames.size() < 3) return;
  std::vector<double> steps;
  for (std::size_t i = 1; i < frames.size(); ++i) steps.push_back(frames[i].t - frames[i - 1].t);
  const double median = UpperMedian(steps);
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (steps[i] <= factor * median) continue;
    const long missing = std::lround(steps[i] / median) - 1;
    warnings->push_back(camera_name + ":" + std::to_string(frames[i + 1].line) + ": about " +
                        std::to_string(missing) + " image(s) dropped before this one (a step of " +
                        Seconds(steps[i]) + ", the median step is " + Seconds(median) + ")");
  }
}

}  // namespace

std::string FrameSkip::ToString() const {
  return file + ":" + std::to_string(line) + ": " + reason;
}

std::vector<std::string> ToStrings(const std::vector<FrameSkip>& skips) {
  std::vector<std::string> out;
  for (const FrameSkip& s : skips) out.push_back(s.ToString());
  return out;
}

std::vector<EurocFrame> ParseEurocCameraCsv(const std::string& text, const std::string& name,
                                            const std::string& image_dir, std::int64_t origin_ns,
                                            std::vector<FrameSkip>* skipped) {
  std::vector<EurocFrame> frames;
  std::stringstream in(text);
  std::string row;
  std::int64_t last_ns = -1;
  int line = 0, rows = 0;
  while (std::getline(in, row)) {
    ++line;
    if (Trim(row).empty() || Trim(row)[0] == '#') continue;
    ++rows;
    const std::string where = name + ":" + std::to_string(line);
    const std::size_t comma = row.find(',');
    if (comma == std::string::npos || row.find(',', comma + 1) != std::string::npos) {
      throw IoError(where, "expected 2 comma-separated fields (timestamp [ns],filename)");
    }
    const std::int64_t ns = ParseEurocNanoseconds(Trim(row.substr(0, comma)), where);
    const std::string file = Trim(row.substr(comma + 1));
    if (file.empty()) throw IoError(where, "empty filename");
    const fs::path image = fs::path(image_dir) / file;
    std::string problem;
    if (ns == last_ns) problem = "duplicated timestamp (the previous row has the same)";
    if (ns < last_ns) problem = "timestamp goes back";
    if (problem.empty() && (fs::path(file).is_absolute() || file.find("..") != std::string::npos)) {
      problem = "'" + file + "' is not a file name inside " + image_dir;
    }
    if (problem.empty() && !fs::is_regular_file(image)) {
      problem = "image file missing: " + image.string();
    }
    if (!problem.empty()) {
      skipped->push_back({name, line, problem});
      continue;
    }
    last_ns = ns;
    frames.push_back({static_cast<double>(ns - origin_ns) * 1e-9, image.string(), line});
  }
  if (rows == 0) throw IoError(name, "empty file: no data rows");
  return frames;
}

void CheckImuCoverage(const std::vector<sensor::ImuSample>& imu, const EurocDatasetOptions& options,
                      const std::string& camera_name, const std::string& imu_name,
                      std::vector<EurocFrame>* frames, std::vector<FrameSkip>* skipped,
                      std::vector<std::string>* warnings) {
  if (imu.empty() || frames->empty()) return;
  if (frames->back().t < imu.front().t || frames->front().t > imu.back().t) {
    throw IoError(camera_name, "the camera times [" + Seconds(frames->front().t) + ", " +
                                   Seconds(frames->back().t) + "] do not overlap the IMU's [" +
                                   Seconds(imu.front().t) + ", " + Seconds(imu.back().t) +
                                   "] (clocks not synchronised, or another recording's IMU?)");
  }
  const std::vector<Interval> gaps = ImuGaps(imu, options.max_imu_gap_s);
  for (const Interval& g : gaps) {
    warnings->push_back(imu_name + ": a gap of " + Seconds(g.end - g.begin) + " from " +
                        Seconds(g.begin) + " (longer than " + Seconds(options.max_imu_gap_s) + ")");
  }
  std::vector<EurocFrame> covered;
  for (const EurocFrame& f : *frames) {
    const std::string problem = CoverageProblem(imu, gaps, f.t);
    if (problem.empty()) {
      covered.push_back(f);
    } else {
      skipped->push_back({camera_name, f.line, problem, f.t});
    }
  }
  *frames = std::move(covered);
  WarnDroppedFrames(*frames, options.dropped_frame_factor, camera_name, warnings);
}

EurocDataset ReadEurocDataset(const std::string& dir, const EurocDatasetOptions& options) {
  fs::path mav0 = fs::path(dir) / "mav0";
  if (!fs::is_directory(mav0)) mav0 = fs::path(dir);
  const fs::path cam_csv = mav0 / "cam0" / "data.csv";
  if (!fs::is_regular_file(cam_csv))
    throw IoError(dir, "not a EuRoC folder: no mav0/cam0/data.csv");
  EurocDataset d;
  d.imu = ReadEurocImuRecording(dir);
  d.cam0 = ReadEurocCamera((mav0 / "cam0" / "sensor.yaml").string());
  d.frames = ParseEurocCameraCsv(ReadFileToString(cam_csv.string()), cam_csv.string(),
                                 (mav0 / "cam0" / "data").string(), d.imu.origin_ns, &d.skipped);
  CheckImuCoverage(d.imu.imu, options, cam_csv.string(), (mav0 / "imu0" / "data.csv").string(),
                   &d.frames, &d.skipped, &d.warnings);
  if (d.frames.empty()) {
    throw IoError(cam_csv.string(),
                  "no usable frame; the first skipped: " + d.skipped.front().ToString());
  }
  return d;
}

}  // namespace io
}  // namespace plucker
