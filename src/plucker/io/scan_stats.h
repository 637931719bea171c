// Statistics every LiDAR scan reader returns next to the scan, so that the caller can report
// what was dropped (the readers themselves never print).
#pragma once

#include <cstddef>

namespace plucker {
namespace io {

struct ScanReadStats {
  std::size_t points_in_file = 0;  // records present in the file
  std::size_t non_finite_dropped =
      0;  // records with a NaN/Inf coordinate, dropped (never passed on)
};

}  // namespace io
}  // namespace plucker
