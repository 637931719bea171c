#include "plucker/eval/point_tracks.h"

#include <algorithm>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>

#include "plucker/geometry/point_projection.h"
#include "plucker/geometry/point_triangulation.h"

namespace plucker {
namespace eval {
namespace {

// The track's largest reprojection error, or nothing when it cannot be triangulated.
std::optional<double> WorstReprojection(const PinholeIntrinsics& K, const std::vector<SE3d>& poses,
                                        const std::vector<Eigen::Vector2d>& uv) {
  PointTriangulationOptions o;
  o.min_parallax_deg = 0.0;  // judged by the reprojection only
  const PointTriangulationResult t = TriangulatePoint(K, poses, uv, o);
  if (!t.ok()) return std::nullopt;
  double worst = 0.0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const std::optional<Eigen::Vector2d> q = ProjectPoint(K, poses[i], t.p_w);
    worst = std::max(worst, q ? (*q - uv[i]).norm() : std::numeric_limits<double>::infinity());
  }
  return worst;
}

}  // namespace

PointTrackQuality EvaluatePointTracks(const PinholeIntrinsics& K, const std::vector<SE3d>& T_w_c,
                                      const std::vector<sensor::PointObservation>& observations,
                                      const PointTrackQualityOptions& options) {
  if (!K.IsValid()) throw std::invalid_argument("EvaluatePointTracks: invalid intrinsics");
  if (options.min_views < 2 || !(options.max_error_px > 0)) {
    throw std::invalid_argument("EvaluatePointTracks: min_views must be >= 2, max_error_px > 0");
  }
  std::map<int, std::pair<std::vector<SE3d>, std::vector<Eigen::Vector2d>>> tracks;
  for (const sensor::PointObservation& o : observations) {
    if (o.point_id < 0) continue;
    if (o.frame < 0 || o.frame >= static_cast<int>(T_w_c.size())) {
      throw std::invalid_argument("EvaluatePointTracks: frame " + std::to_string(o.frame) +
                                  " has no pose (" + std::to_string(T_w_c.size()) + " poses)");
    }
    tracks[o.point_id].first.push_back(T_w_c[o.frame]);
    tracks[o.point_id].second.push_back(o.uv);
  }
  PointTrackQuality q;
  q.tracks = static_cast<int>(tracks.size());
  for (const auto& [id, track] : tracks) {
    PointTrackResult r;
    r.point_id = id;
    r.views = static_cast<int>(track.first.size());
    if (r.views >= options.min_views) {
      ++q.evaluated;
      const std::optional<double> worst = WorstReprojection(K, track.first, track.second);
      r.judged = worst.has_value();
      r.max_error_px = worst.value_or(0.0);
      q.failed += !r.judged;
      q.correct += r.judged && r.max_error_px <= options.max_error_px;
      q.wrong += r.judged && !(r.max_error_px <= options.max_error_px);
    }
    q.results.push_back(r);
  }
  return q;
}

}  // namespace eval
}  // namespace plucker
