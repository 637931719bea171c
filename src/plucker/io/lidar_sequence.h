// Streaming access to a LiDAR sequence on disk: only the file list is held in memory, each frame
// is read on demand, so memory does not grow with the number of frames.
//
// Layouts recognised by Open(dir, sequence):
//   1. KITTI sequence folder: DIR/velodyne/NNNNNN.bin [+ DIR/calib.txt, DIR/times.txt].
//   2. KITTI dataset root with sequence="00": DIR/sequences/00/... as in 1.
//   3. Simulator output with per-point time: DIR/pcd/NNNNNN.pcd (preferred over DIR/velodyne/
//      when both exist, because it carries the point times needed for deskewing).
//   4. A folder of .pcd files sorted by name (DIR/*.pcd), times.txt optional.
// Numeric file names (KITTI, sim, numbered PCD) define the frame index; a gap in the numbering
// (000003.bin absent between 000002 and 000004) is a `missing` slot. For non-numeric PCD names the
// frames are the files sorted by name; when every name parses as a number (e.g. ROS stamps
// "1634567890.123456.pcd") and there is no times.txt, those numbers are the frame times.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "plucker/geometry/se3.h"
#include "plucker/io/io_error.h"
#include "plucker/io/scan_stats.h"
#include "plucker/sensor/lidar_scan.h"

namespace plucker {
namespace io {

struct LidarFrameRef {
  std::size_t index = 0;  // frame number (the file number for numbered files)
  std::string path;       // file path (the expected path for a missing slot)
  bool missing = false;   // a gap in the numbering
};

class LidarSequence {
 public:
  enum class Format { kKittiBin, kPcd };

  // See the layouts above. Throws IoError for an unreadable/nonexistent folder, a folder with no
  // frames, a malformed calib.txt Tr or times.txt, or times.txt with fewer lines than frames.
  static LidarSequence Open(const std::string& dir, const std::string& sequence = "");

  std::size_t size() const { return frames_.size(); }  // frames including missing slots
  const LidarFrameRef& frame(std::size_t i) const { return frames_.at(i); }
  std::size_t num_missing() const;

  // Reads frame i (scan.timestamp = times()[i] when known). Per-frame problems (missing slot or
  // file, truncated, empty, unreadable, malformed) return false with `error` set to
  // "<file>: <problem>"; the caller skips the frame and records it. Never throws for those.
  // `stats` (optional) receives the NaN/Inf points dropped. The file bytes go through a buffer
  // owned by the sequence and the scan's channels are refilled in place, so reading frame after
  // frame into the same scan allocates nothing once the buffers are large enough (not for
  // concurrent calls on one sequence). On failure *scan is unspecified.
  bool Read(std::size_t i, LidarScan* scan, std::string* error,
            ScanReadStats* stats = nullptr) const;

  const std::optional<SE3d>& T_cam0_velo() const { return T_cam0_velo_; }  // calib.txt Tr
  bool has_calib() const { return has_calib_; }  // calib.txt exists (may lack Tr)
  // From times.txt (one per frame slot) when present, else from numeric PCD file names, else
  // empty (the caller then assumes 10 Hz).
  const std::vector<double>& times() const { return times_; }
  bool has_point_time() const { return has_point_time_; }  // PCD frames with a time field
  Format format() const { return format_; }
  const std::string& root() const { return root_; }  // folder holding calib.txt/times.txt
  std::string description() const;  // "KITTI sequence at DIR, 16 frames (1 missing), calib Tr"

 private:
  std::string root_;
  Format format_ = Format::kKittiBin;
  std::vector<LidarFrameRef> frames_;
  std::optional<SE3d> T_cam0_velo_;
  bool has_calib_ = false;
  std::vector<double> times_;
  bool has_point_time_ = false;
  mutable std::string read_buffer_;  // file bytes of the last Read, reused
};

}  // namespace io
}  // namespace plucker
