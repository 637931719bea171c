#include "vio_tracks.h"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "plucker/io/io_error.h"

namespace plucker {
namespace app {

VioTrackWriter::VioTrackWriter(odometry::VisualInertialOdometry* vio) : vio_(vio) {
  vio->SetFrameObserver([this](int i, const window::FrameInput& frame, const SE3d&,
                               const window::SlidingWindowEstimator& map) {
    frames_[i] = frame;
    std::vector<int>& ids = window_lines_[i];
    ids.clear();
    for (const auto& [id, line] : map.Lines()) ids.push_back(id);
  });
}

void VioTrackWriter::Write(const std::string& dir,
                           std::optional<std::int64_t> clock_origin_ns) const {
  std::filesystem::create_directories(dir);
  std::ostringstream points, segments, frames, lines;
  for (std::ostringstream* s : {&points, &segments, &frames}) *s << std::setprecision(10);
  lines << "# frame line_id (in the window's map)\n";
  for (const auto& [i, ids] : window_lines_)
    for (const int id : ids) lines << i << ' ' << id << '\n';
  points << "# frame point_id u v (undistorted px)\n";
  segments << "# frame line_id su sv eu ev (undistorted px)\n";
  frames << "# frame t fx fy cx cy\n";
  const PinholeIntrinsics& K = vio_->K();
  for (const auto& [i, f] : frames_) {
    const double t_ns = std::round(f.time * 1e9) + static_cast<double>(clock_origin_ns.value_or(0));
    frames << i << ' ' << std::fixed << std::setprecision(9) << t_ns * 1e-9 << std::defaultfloat
           << std::setprecision(10) << ' ' << K.fx << ' ' << K.fy << ' ' << K.cx << ' ' << K.cy
           << '\n';
    for (const sensor::PointObservation& p : f.points)
      points << i << ' ' << p.point_id << ' ' << p.uv.x() << ' ' << p.uv.y() << '\n';
    for (const sensor::SegmentObservation& s : f.segments) {
      segments << i << ' ' << s.line_id << ' ' << s.s_px.x() << ' ' << s.s_px.y() << ' '
               << s.e_px.x() << ' ' << s.e_px.y() << '\n';
    }
  }
  io::WriteFileAtomically(dir + "/points.txt", points.str());
  io::WriteFileAtomically(dir + "/segments.txt", segments.str());
  io::WriteFileAtomically(dir + "/frames.txt", frames.str());
  io::WriteFileAtomically(dir + "/window_lines.txt", lines.str());
}

}  // namespace app
}  // namespace plucker
