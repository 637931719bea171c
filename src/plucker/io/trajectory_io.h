// Trajectory files: KITTI odometry poses and TUM RGB-D trajectories.
//
// KITTI: one pose a line, 12 numbers = the 3x4 matrix [R | t] of T_ref_frame, row-major.
// TUM:   one pose a line, 8 numbers `t tx ty tz qx qy qz qw`; lines starting with '#' are
//        comments. Timestamps must not decrease.
// Every reader throws io::IoError whose message names the file AND the line ("file:12: ...")
// for: a wrong field count, a non-numeric field, NaN/Inf, a KITTI 3x3 block that is not a
// rotation (small errors, max |R^T R - I| <= 1e-3 and det > 0, are re-orthonormalised; larger
// ones rejected), a quaternion whose norm is not near 1 (|1 - |q|| <= 1e-3 is normalised;
// zero or far-from-unit rejected), decreasing TUM timestamps, and an empty file.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "plucker/geometry/se3.h"
#include "plucker/io/io_error.h"

namespace plucker {
namespace io {

enum class TrajectoryFormat { kAuto, kKitti, kTum };

// A problem at a line of a file: what() is "file:line: problem", path() is "file:line".
class TrajectoryParseError : public IoError {
 public:
  TrajectoryParseError(const std::string& file, int line, const std::string& problem)
      : IoError(file + ":" + std::to_string(line), problem), file_(file), line_(line) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }  // 1-based

 private:
  std::string file_;
  int line_;
};

struct Trajectory {
  std::vector<double> times;  // seconds; empty for KITTI files (see ReadTimes)
  std::vector<SE3d> poses;    // T_ref_frame, one per line
};

// Reads a trajectory file; kAuto decides by the field count of the first data line
// (12 -> KITTI, 8 -> TUM). Throws IoError.
Trajectory ReadTrajectory(const std::string& path,
                          TrajectoryFormat format = TrajectoryFormat::kAuto);

// Parses the text of a trajectory file; `name` is used in error messages. Throws IoError.
Trajectory ParseTrajectory(const std::string& text, const std::string& name,
                           TrajectoryFormat format);

// Writes KITTI poses (12 numbers a line, shortest text that reads back to the same double),
// atomically. Throws IoError.
void WriteKittiPoses(const std::string& path, const std::vector<SE3d>& poses);

// Writes a TUM trajectory (`t tx ty tz qx qy qz qw`, shortest exact text), atomically; each of
// `comments` is a line "# ..." after the column header (what the file holds). Throws IoError
// (also if the sizes differ).
void WriteTumTrajectory(const std::string& path, const std::vector<double>& times,
                        const std::vector<SE3d>& poses,
                        const std::vector<std::string>& comments = {});

// A TUM trajectory on a recording's own clock: each time is `origin_ns` (integer nanoseconds, e.g.
// EuRoC's first IMU timestamp) plus times[i] seconds, rounded to the nanosecond and written as
// exact decimal seconds with nine digits (`1403638538.577829376`), so that the stamps read back as
// the dataset's own (evo, `plucker eval`). `header` lines (without '#') are written first as
// comments, e.g. the frame the poses are in, then a comment saying the stamps are on the
// recording's clock. Throws IoError (also if the sizes differ, or a time is
// not finite).
void WriteTumTrajectoryOnClock(const std::string& path, std::int64_t origin_ns,
                               const std::vector<double>& times, const std::vector<SE3d>& poses,
                               const std::vector<std::string>& header = {});
// The text of one such stamp: integer nanoseconds as decimal seconds (nine digits after the point).
std::string FormatNanosecondsAsSeconds(std::int64_t ns);

// KITTI poses of a set of cameras of which some may be missing (e.g. views a reconstruction did
// not register): a missing camera is a line of twelve `nan`. Same errors as ReadTrajectory
// otherwise (a NaN among numbers is rejected).
std::vector<std::optional<SE3d>> ReadKittiPosesWithGaps(const std::string& path);
void WriteKittiPosesWithGaps(const std::string& path,
                             const std::vector<std::optional<SE3d>>& poses);

// Reads a KITTI times.txt (one number a line, non-decreasing). Throws IoError.
std::vector<double> ReadTimes(const std::string& path);

// The name of a format ("auto", "kitti", "tum") and its parse (throws std::invalid_argument).
std::string FormatName(TrajectoryFormat format);
TrajectoryFormat ParseTrajectoryFormat(const std::string& name);

}  // namespace io
}  // namespace plucker
