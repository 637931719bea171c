#include "plucker/vision/line_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#include <opencv2/calib3d.hpp>

#include "plucker/geometry/so3.h"
#include "plucker/vision/point_tracker.h"

namespace plucker {
namespace vision {
LineTracker::LineTracker(const LineTrackerOptions& options) : options_(options) {
  if (options_.max_lost_frames < 0) {
    throw std::invalid_argument("LineTracker: max_lost_frames must be >= 0");
  }
  if (options_.flow_samples > 0 &&
      (options_.flow_window_px < 3 || options_.flow_levels < 0 || options_.flow_iterations < 1)) {
    throw std::invalid_argument(
        "LineTracker: flow_window_px must be >= 3, flow_levels >= 0, flow_iterations >= 1");
  }
  const LineMatcherOptions& m = options_.match;
  if (m.max_hamming < 0 || !(m.ratio > 0 && m.ratio <= 1) || !(m.max_angle_deg > 0) ||
      !(m.max_length_ratio >= 1) || !(m.min_epipolar_overlap >= 0 && m.min_epipolar_overlap <= 1)) {
    throw std::invalid_argument("LineTracker: invalid matcher options");
  }
}

void LineTracker::DescribeTracks(const std::vector<int>& track_index, LineTrackerStats* st) {
  for (const auto& [frame, image] : images_) {
    std::vector<int> todo;
    std::vector<Segment2d> segments;
    for (const int k : track_index) {
      TrackState& t = tracks_[k];
      if (t.descriptor_frame == t.last_frame || t.last_frame != frame) continue;
      todo.push_back(k);
      segments.push_back(t.observed);
    }
    if (todo.empty()) continue;
    const cv::Mat d = ComputeLineDescriptors(image, segments, options_.describe);
    st->lbd_described += static_cast<int>(todo.size());
    for (std::size_t i = 0; i < todo.size(); ++i) {
      tracks_[todo[i]].descriptor = d.row(static_cast<int>(i)).clone();
      tracks_[todo[i]].descriptor_frame = frame;
    }
  }
}

std::vector<LineMatch> LineTracker::Associate(const std::vector<int>& candidate_index,
                                              const LinePredictions& predictions,
                                              const cv::Mat& gray, const LineFeatures& current,
                                              const std::optional<Eigen::Matrix3d>& F_cur_prev,
                                              std::vector<cv::Mat>* current_descriptors,
                                              LineTrackerStats* st) {
  const bool use_flow = options_.flow_samples > 0;
  LineFeatures tracks;
  for (const int k : candidate_index) tracks.segments.push_back(tracks_[k].segment);
  const std::vector<GatedPair> gated = GateLinePairs(tracks, current, options_.match, F_cur_prev,
                                                     use_flow ? &predictions : nullptr, &st->match);
  std::vector<int> degree_a(tracks.size(), 0), degree_b(current.size(), 0);
  for (const GatedPair& g : gated) ++degree_a[g.a], ++degree_b[g.b];
  std::vector<LineMatch> matches;
  std::vector<int> sub_a, sub_b;  // with several candidates: matched by descriptors
  std::vector<bool> clean_a(tracks.size(), false), clean_b(current.size(), false);
  for (const GatedPair& g : gated) {
    if (options_.flow_first && use_flow && !predictions[g.a].empty() && degree_a[g.a] == 1 &&
        degree_b[g.b] == 1) {
      clean_a[g.a] = clean_b[g.b] = true;
      matches.push_back({g.a, g.b, -1, g.overlap});
      ++st->flow_matched;
    }
  }
  for (int i = 0; i < tracks.size(); ++i) {
    if (degree_a[i] == 0) ++st->match.no_candidate;
    if (degree_a[i] > 0 && !clean_a[i]) sub_a.push_back(i);
  }
  for (int j = 0; j < current.size(); ++j) {
    if (degree_b[j] > 0 && !clean_b[j]) sub_b.push_back(j);
  }
  if (!sub_a.empty()) {
    std::vector<int> track_index;
    for (const int i : sub_a) track_index.push_back(candidate_index[i]);
    DescribeTracks(track_index, st);
    LineFeatures a, b;
    LinePredictions sub_predictions;
    for (const int i : sub_a) {
      if (tracks_[candidate_index[i]].descriptor_frame != tracks_[candidate_index[i]].last_frame) {
        throw std::logic_error("LineTracker: no image kept for a track's latest observation");
      }
      a.segments.push_back(tracks.segments[i]);
      a.descriptors.push_back(tracks_[candidate_index[i]].descriptor);
      sub_predictions.push_back(predictions[i]);
    }
    for (const int j : sub_b) b.segments.push_back(current.segments[j]);
    b.descriptors = ComputeLineDescriptors(gray, b.segments, options_.describe);
    st->lbd_described += b.size();
    current_descriptors->assign(current.size(), cv::Mat());
    for (int r = 0; r < b.size(); ++r) (*current_descriptors)[sub_b[r]] = b.descriptors.row(r);
    const LineMatchResult r =
        MatchLines(a, b, options_.match, F_cur_prev, use_flow ? &sub_predictions : nullptr);
    st->match.no_candidate += r.stats.no_candidate;
    st->match.rejected_hamming += r.stats.rejected_hamming;
    st->match.rejected_ratio += r.stats.rejected_ratio;
    st->match.rejected_mutual += r.stats.rejected_mutual;
    for (const LineMatch& m : r.matches)
      matches.push_back({sub_a[m.a], sub_b[m.b], m.distance, m.overlap});
  }
  std::sort(matches.begin(), matches.end(),
            [](const LineMatch& x, const LineMatch& y) { return x.a < y.a; });
  st->match.matches = static_cast<int>(matches.size());
  return matches;
}

LinePredictions LineTracker::Predict(const std::vector<const TrackState*>& tracks,
                                     const FlowPyramid& pyramid, int* predicted) const {
  LinePredictions out(tracks.size());
  const int n = options_.flow_samples;
  if (n <= 0 || tracks.empty() || previous_.empty() || pyramid.empty()) return out;
  std::vector<cv::Point2f> from, to;
  for (const TrackState* t : tracks) {
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector2d p =
          t->segment.head<2>() + (k + 0.5) / n * (t->segment.tail<2>() - t->segment.head<2>());
      from.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
    }
  }
  std::vector<unsigned char> status;
  PyramidFlow(previous_, pyramid, from, options_.flow_window_px, options_.flow_levels, &to, &status,
              options_.flow_iterations);
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    for (int k = 0; k < n; ++k) {
      const std::size_t j = i * n + k;
      if (status[j] && std::isfinite(to[j].x) && std::isfinite(to[j].y)) {
        out[i].emplace_back(to[j].x, to[j].y);
      }
    }
    // Fewer than half the samples followed: no prediction (the gate is skipped).
    if (2 * static_cast<int>(out[i].size()) < n) out[i].clear();
    if (!out[i].empty()) ++*predicted;
  }
  return out;
}

LineTrackerFrame LineTracker::Track(const cv::Mat& gray, const std::vector<Segment2d>& segments,
                                    const std::optional<Eigen::Matrix3d>& F_cur_prev) {
  if (gray.empty() || gray.type() != CV_8UC1) {
    throw std::invalid_argument("LineTracker: the image must be non-empty 8-bit grayscale");
  }
  const FlowPyramid pyramid = options_.flow_samples > 0
                                  ? FlowPyramid(gray, options_.flow_window_px, options_.flow_levels)
                                  : FlowPyramid();
  return TrackImpl(gray, pyramid, segments, F_cur_prev);
}

LineTrackerFrame LineTracker::Track(const FlowPyramid& pyramid,
                                    const std::vector<Segment2d>& segments,
                                    const std::optional<Eigen::Matrix3d>& F_cur_prev) {
  if (pyramid.empty()) throw std::invalid_argument("LineTracker: empty pyramid");
  if (options_.flow_samples > 0 && pyramid.window_px() < options_.flow_window_px) {
    throw std::invalid_argument("LineTracker: pyramid built for a window of " +
                                std::to_string(pyramid.window_px()) + " px < flow_window_px " +
                                std::to_string(options_.flow_window_px));
  }
  return TrackImpl(pyramid.image(), pyramid, segments, F_cur_prev);
}

LineTrackerFrame LineTracker::TrackImpl(const cv::Mat& gray, const FlowPyramid& pyramid,
                                        const std::vector<Segment2d>& segments,
                                        const std::optional<Eigen::Matrix3d>& F_cur_prev) {
  if (gray.empty() || gray.type() != CV_8UC1) {
    throw std::invalid_argument("LineTracker: the image must be non-empty 8-bit grayscale");
  }
  if (frame_ > 0 && gray.size() != size_) {
    throw std::invalid_argument("LineTracker: image of " + std::to_string(gray.cols) + "x" +
                                std::to_string(gray.rows) + " after " +
                                std::to_string(size_.width) + "x" + std::to_string(size_.height));
  }
  size_ = gray.size();
  LineTrackerFrame out;
  out.frame = frame_++;
  LineTrackerStats& st = out.stats;
  st.epipolar_gate = F_cur_prev.has_value();
  const LineFeatures current = PrepareLines(gray, segments, options_.describe, &st.description);
  std::vector<int> track_of(current.size(), -1);  // index into tracks_ for each segment

  // 2.-3. Every live track (seen in the previous frame, or lost for up to max_lost_frames frames
  // and coasting on its flow prediction) against the new segments.
  const std::vector<const TrackState*> all = [&] {
    std::vector<const TrackState*> v;
    for (const TrackState& t : tracks_) v.push_back(&t);
    return v;
  }();
  LinePredictions all_predictions = Predict(all, pyramid, &st.predicted);
  std::vector<int> candidate_index;
  LinePredictions predictions;
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    // A lost track has no last observation in the previous frame: without a flow prediction no
    // gate would tie it to its place, so it is not matched (and ends below).
    if (tracks_[k].last_frame != out.frame - 1 && all_predictions[k].empty()) continue;
    candidate_index.push_back(static_cast<int>(k));
    predictions.push_back(all_predictions[k]);
  }
  std::vector<cv::Mat> descriptors;  // of the current segments that needed one (others: empty)
  const std::vector<LineMatch> matches =
      Associate(candidate_index, predictions, gray, current, F_cur_prev, &descriptors, &st);
  for (const LineMatch& m : matches) {
    const int k = candidate_index[m.a];
    track_of[m.b] = k;
    ++(tracks_[k].last_frame == out.frame - 1 ? st.continued : st.reassociated);
  }

  // 4. Update the tracks, start new ones, drop the old ones.
  std::vector<bool> seen(tracks_.size(), false);
  for (int j = 0; j < current.size(); ++j) {
    if (track_of[j] >= 0) seen[track_of[j]] = true;
  }
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    if (seen[k]) continue;
    if (tracks_[k].last_frame == out.frame - 1) ++st.lost;
    // Coast on the flow prediction (the segment through the first and last followed points),
    // or end now without one.
    if (all_predictions[k].size() >= 2) {
      const Eigen::Vector2d a = all_predictions[k].front(), b = all_predictions[k].back();
      tracks_[k].segment = Segment2d(a.x(), a.y(), b.x(), b.y());
    } else {
      tracks_[k].last_frame = std::numeric_limits<int>::min() / 2;
    }
  }
  for (int j = 0; j < current.size(); ++j) {
    if (track_of[j] < 0) {
      TrackState t;
      t.id = next_id_++;
      tracks_.push_back(t);
      track_of[j] = static_cast<int>(tracks_.size()) - 1;
      ++st.started;
    }
    TrackState& t = tracks_[track_of[j]];
    t.last_frame = out.frame;
    t.segment = t.observed = current.segments[j];
    if (j < static_cast<int>(descriptors.size()) && !descriptors[j].empty()) {
      t.descriptor = descriptors[j].clone();
      t.descriptor_frame = out.frame;
    }
    sensor::SegmentObservation o;
    o.frame = out.frame;
    o.line_id = t.id;
    o.s_px = current.segments[j].head<2>();
    o.e_px = current.segments[j].tail<2>();
    out.observations.push_back(o);
  }
  const std::size_t before = tracks_.size();
  tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(),
                               [&](const TrackState& t) {
                                 return t.last_frame < out.frame - options_.max_lost_frames;
                               }),
                tracks_.end());
  st.ended = static_cast<int>(before - tracks_.size());
  previous_ = pyramid;
  images_.emplace_back(out.frame, pyramid.empty() ? gray.clone() : pyramid.image());
  while (!images_.empty() && images_.front().first < out.frame - options_.max_lost_frames) {
    images_.erase(images_.begin());
  }
  return out;
}

std::optional<Eigen::Matrix3d> FundamentalFromPointTracks(
    const std::vector<sensor::PointObservation>& previous,
    const std::vector<sensor::PointObservation>& current, const std::optional<PinholeIntrinsics>& K,
    double threshold_px, int min_points) {
  std::map<int, Eigen::Vector2d> prev_by_id;
  for (const auto& o : previous) prev_by_id[o.point_id] = o.uv;
  std::vector<cv::Point2d> p0, p1;
  for (const auto& o : current) {
    const auto it = prev_by_id.find(o.point_id);
    if (it == prev_by_id.end() || o.point_id < 0) continue;
    p0.emplace_back(it->second.x(), it->second.y());
    p1.emplace_back(o.uv.x(), o.uv.y());
  }
  if (static_cast<int>(p0.size()) < std::max(min_points, 8)) return std::nullopt;
  const cv::Mat model = EpipolarModel(p0, p1, K, threshold_px, 0.999);
  return FundamentalOfModel(model, K);  // none, or several solutions: nullopt
}

Eigen::Matrix3d FundamentalFromPoses(const PinholeIntrinsics& K, const SE3d& T_w_a,
                                     const SE3d& T_w_b) {
  const SE3d T_b_a = T_w_b.Inverse() * T_w_a;
  const Eigen::Matrix3d E = Hat(T_b_a.translation()) * T_b_a.rotation().toRotationMatrix();
  const Eigen::Matrix3d K_inv = K.K().inverse();
  return K_inv.transpose() * E * K_inv;
}

}  // namespace vision
}  // namespace plucker
