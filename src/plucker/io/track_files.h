// Track files of the visual front end (`plucker lines track`), in the rows of the simulator's
// sequence format (docs/sim-format.md), so that an estimator reads either the same way:
//   segments.txt  `frame line_id su sv eu ev`   (sensor::SegmentObservation, pixels)
//   points.txt    `frame point_id u v`          (sensor::PointObservation, pixels)
// '#' starts a comment line. The readers validate the field count, numbers, finiteness, frame
// >= 0 and id >= -1, and throw IoError naming the file and the line ("file:12: ...").
#pragma once

#include <string>
#include <vector>

#include "plucker/io/io_error.h"
#include "plucker/sensor/camera_observations.h"

namespace plucker {
namespace io {

std::vector<sensor::SegmentObservation> ParseSegmentTracks(const std::string& text,
                                                           const std::string& name);
std::vector<sensor::SegmentObservation> ReadSegmentTracks(const std::string& path);
// header: comment lines (without '#'). Atomic write; throws IoError.
void WriteSegmentTracks(const std::string& path,
                        const std::vector<sensor::SegmentObservation>& observations,
                        const std::vector<std::string>& header = {});

std::vector<sensor::PointObservation> ParsePointTracks(const std::string& text,
                                                       const std::string& name);
std::vector<sensor::PointObservation> ReadPointTracks(const std::string& path);
void WritePointTracks(const std::string& path,
                      const std::vector<sensor::PointObservation>& observations,
                      const std::vector<std::string>& header = {});

}  // namespace io
}  // namespace plucker
