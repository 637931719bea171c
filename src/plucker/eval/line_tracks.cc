#include "plucker/eval/line_tracks.h"

#include <algorithm>
#include <limits>
#include <set>
#include <stdexcept>
#include <utility>

namespace plucker {
namespace eval {

const char* ToString(TrackVerdict verdict) {
  switch (verdict) {
    case TrackVerdict::kCorrect:
      return "correct";
    case TrackVerdict::kWrong:
      return "wrong";
    case TrackVerdict::kUnconstrained:
      return "unconstrained";
    case TrackVerdict::kShort:
      return "short";
  }
  return "unknown";
}

namespace {

LineTrackResult Judge(const PinholeIntrinsics& K, const std::vector<LineObservation>& obs,
                      const LineTrackQualityOptions& options, LineTrackResult r) {
  if (r.views < options.min_views) return r;
  // The verdict is about the reprojection of the line only: cheirality and the N-view
  // agreement test are off (a wrong track shows as a large reprojection error instead).
  LineTriangulationOptions triangulation = options.triangulation;
  triangulation.min_depth = -std::numeric_limits<double>::infinity();
  triangulation.max_sigma_ratio = std::numeric_limits<double>::infinity();
  const LineTriangulationResult tri = TriangulateLineRefined(K, obs, triangulation);
  if (tri.status == LineTriangulationStatus::kSmallParallax) {
    r.verdict = TrackVerdict::kUnconstrained;
    r.reason = tri.message;
    return r;
  }
  if (!tri.ok()) {  // an endpoint ray exactly along the line, non-finite input
    r.verdict = TrackVerdict::kWrong;
    r.reason = tri.message;
    return r;
  }
  r.max_error_px = tri.max_error_px;
  r.verdict =
      tri.max_error_px <= options.max_error_px ? TrackVerdict::kCorrect : TrackVerdict::kWrong;
  return r;
}

}  // namespace

LineTrackQuality EvaluateLineTracks(const PinholeIntrinsics& K, const std::vector<SE3d>& T_w_c,
                                    const std::vector<sensor::SegmentObservation>& observations,
                                    const LineTrackQualityOptions& options) {
  if (!K.IsValid()) throw std::invalid_argument("EvaluateLineTracks: invalid intrinsics");
  if (options.min_views < 2 || !(options.max_error_px > 0)) {
    throw std::invalid_argument("EvaluateLineTracks: min_views must be >= 2, max_error_px > 0");
  }
  std::map<int, std::vector<LineObservation>> tracks;
  std::map<int, std::pair<int, int>> span;
  std::set<std::pair<int, int>> seen;  // (line_id, frame)
  std::set<int> frames;
  LineTrackQuality q;
  for (const sensor::SegmentObservation& o : observations) {
    if (o.line_id < 0) continue;
    if (o.frame < 0 || o.frame >= static_cast<int>(T_w_c.size())) {
      throw std::invalid_argument("EvaluateLineTracks: frame " + std::to_string(o.frame) +
                                  " has no pose (" + std::to_string(T_w_c.size()) + " poses)");
    }
    if (!seen.insert({o.line_id, o.frame}).second) {
      throw std::invalid_argument("EvaluateLineTracks: track " + std::to_string(o.line_id) +
                                  " observed twice in frame " + std::to_string(o.frame));
    }
    LineObservation lo;
    lo.T_w_c = T_w_c[o.frame];
    lo.start = o.s_px;
    lo.end = o.e_px;
    tracks[o.line_id].push_back(lo);
    auto it = span.find(o.line_id);
    if (it == span.end()) {
      span[o.line_id] = {o.frame, o.frame};
    } else {
      it->second.first = std::min(it->second.first, o.frame);
      it->second.second = std::max(it->second.second, o.frame);
    }
    frames.insert(o.frame);
    ++q.observations;
  }
  q.frames = static_cast<int>(frames.size());
  std::vector<int> lengths;
  long long long_track_observations = 0;
  for (const auto& [id, obs] : tracks) {
    LineTrackResult r;
    r.line_id = id;
    r.views = static_cast<int>(obs.size());
    r.first_frame = span[id].first;
    r.last_frame = span[id].second;
    ++q.length_histogram[r.views];
    r = Judge(K, obs, options, r);
    if (r.views >= options.min_views) {
      ++q.evaluated;
      lengths.push_back(r.views);
      long_track_observations += r.views;
    }
    q.correct += r.verdict == TrackVerdict::kCorrect;
    q.wrong += r.verdict == TrackVerdict::kWrong;
    q.unconstrained += r.verdict == TrackVerdict::kUnconstrained;
    q.results.push_back(r);
  }
  q.tracks = static_cast<int>(tracks.size());
  if (!lengths.empty()) {
    std::sort(lengths.begin(), lengths.end());
    double sum = 0.0;
    for (int l : lengths) sum += l;
    q.mean_length = sum / lengths.size();
    const std::size_t m = lengths.size() / 2;
    q.median_length = lengths.size() % 2 ? lengths[m] : 0.5 * (lengths[m - 1] + lengths[m]);
  }
  q.segments_per_frame = q.frames > 0 ? static_cast<double>(long_track_observations) / q.frames : 0;
  return q;
}

}  // namespace eval
}  // namespace plucker
