// 2D line segment files: one segment a line, `x1 y1 x2 y2` in pixels (origin top-left), fields
// separated by spaces, tabs or commas; blank lines and lines starting with '#' are skipped.
// The York Urban ground truth and `plucker lines detect --out` use this format.
//
// A comment `# detection_ms <number>` records how long the detection of the file's segments
// took (written by `plucker lines detect`, read by `plucker eval lines` for its time column).
//
// Errors name the file and the line ("segs.txt:7: expected 4 numbers, got 3"): a wrong field
// count, a field that is not a number, NaN/Inf, a coordinate beyond +-1e6 px. A file with no
// segment is valid (an image without lines).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "plucker/io/io_error.h"

namespace plucker {
namespace io {

struct SegmentFile {
  std::vector<Eigen::Vector4d> segments;  // x1 y1 x2 y2 [px]
  std::optional<double> detection_ms;     // from a `# detection_ms <number>` comment
};

// Parses the text of a segment file; `name` is used in error messages. Throws IoError.
SegmentFile ParseSegments(const std::string& text, const std::string& name);

// Reads a segment file. Throws IoError (also when it cannot be opened).
SegmentFile ReadSegments(const std::string& path);

// The text of a segment file: `header` lines become '#' comments, then detection_ms when set,
// then one segment a line with 3 decimals.
std::string FormatSegments(const SegmentFile& file, const std::vector<std::string>& header = {});

// Writes FormatSegments(file, header) to path atomically. Throws IoError.
void WriteSegments(const std::string& path, const SegmentFile& file,
                   const std::vector<std::string>& header = {});

}  // namespace io
}  // namespace plucker
