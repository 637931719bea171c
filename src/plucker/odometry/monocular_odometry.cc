#include "plucker/odometry/monocular_odometry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace plucker {
namespace odometry {

using window::FrameInput;
using window::SlidingWindowEstimator;

void MonocularOdometryOptions::Check() const {
  start.Check();
  if (max_lost_frames < 1)
    throw std::invalid_argument("MonocularOdometryOptions: max_lost_frames < 1");
  if (min_stereo_landmarks < 1)
    throw std::invalid_argument("MonocularOdometryOptions: min_stereo_landmarks < 1");
  if (window.T_c0_c1 && window.inertial)
    throw std::invalid_argument("MonocularOdometryOptions: stereo without the inertial mode");
}

const char* ToString(MonocularStatus status) {
  switch (status) {
    case MonocularStatus::kInitializing:
      return "initializing";
    case MonocularStatus::kInitialized:
      return "initialized";
    case MonocularStatus::kReinitialized:
      return "reinitialized";
    case MonocularStatus::kTracking:
      return "tracking";
    case MonocularStatus::kLost:
      return "lost";
  }
  return "?";
}

const char* ToString(MonocularPoseSource source) {
  switch (source) {
    case MonocularPoseSource::kNotLocalized:
      return "not_localized";
    case MonocularPoseSource::kInitialization:
      return "initialization";
    case MonocularPoseSource::kLocalizedBeforeWindow:
      return "localized_before_window";
    case MonocularPoseSource::kTracked:
      return "tracked";
    case MonocularPoseSource::kLost:
      return "lost";
  }
  return "?";
}

struct MonocularOdometry::Impl {
  PinholeIntrinsics K;
  MonocularOdometryOptions options;
  std::unique_ptr<vision::Undistorter> undistorter;
  std::unique_ptr<vision::ImageFrontend> frontend;  // made at the first image
  MonocularFrameObserver frame_observer;
  std::vector<MonocularFrameRecord> records;
  std::vector<MonocularMap> maps;
  MonocularSummary summary;
  std::string start_failure, restart_failure;
  int restart_failed_after = -1;

  std::unique_ptr<SlidingWindowEstimator> estimator;  // the current map
  int a = -1, b = -1;                                 // its two views
  int lost_in_a_row = 0;
  // The start search: frames from `from` on buffered, first view `next_first` searched.
  bool searching = true;
  int from = 0, next_first = 0;
  std::vector<FrameInput> buffer;
  StartSearch search;  // of first view next_first
  std::string message = "no frame pair";

  int last() const { return static_cast<int>(records.size()) - 1; }
  SE3d& pose(int i) { return records[i].T_w_c; }

  void Observe(int i, const FrameInput& frame) {
    if (frame_observer) frame_observer(i, frame, records[i].T_w_c, *estimator);
  }

  // Where a start with first view i is put (the previous map's last two localised frames).
  StartFrame Where(int i) const {
    StartFrame where;
    where.frame = i;
    int l = from - 1;
    while (l >= 1 && !(records[l].has_pose && records[l - 1].has_pose)) --l;
    if (l < 1) return where;
    const SE3d& T1 = records[l].T_w_c;
    const SE3d& T0 = records[l - 1].T_w_c;
    const double step = (T1.translation() - T0.translation()).norm();
    if (!(step > 0.0) || !std::isfinite(step)) return where;
    where.step_length = step;
    const SE3d delta = T0.Inverse() * T1;
    where.T_w_a = T1;
    for (int k = l; k < i; ++k) where.T_w_a = where.T_w_a * delta;
    return where;
  }

  // A new start: its keyframes, the buffered frames before b localised against it.
  void Begin(MonocularStart start, int i) {
    const int map = static_cast<int>(maps.size());
    estimator = std::move(start.estimator);
    const std::vector<SE3d> poses = estimator->KeyframePoses();
    MonocularMap m;
    for (std::size_t k = 0; k < start.keyframes.size(); ++k) {
      const int f = i + start.keyframes[k];
      MonocularFrameRecord& r = records[f];
      r.T_w_c = poses[k];
      r.has_pose = r.keyframe = true;
      r.source = MonocularPoseSource::kInitialization;
      r.map = map;
      m.keyframes.push_back(f);
    }
    summary.keyframes += static_cast<int>(start.keyframes.size());
    a = i;
    b = m.keyframes.back();
    m.first = a;
    m.second = b;
    m.after_lost_frame = from > 0 ? from - 1 : -1;
    m.chained_baseline = start.baseline;
    m.points = start.init.points;
    m.lines = start.init.lines;
    m.tries = start.tries;
    m.chi2_z = start.chi2_z;
    maps.push_back(m);
    for (int f = from; f < b; ++f) {
      MonocularFrameRecord& r = records[f];
      if (r.source == MonocularPoseSource::kInitialization && r.map == map) continue;
      const SE3d guess =
          f < a ? pose(a) : InterpolatePose(pose(a), pose(b), double(f - a) / double(b - a));
      const std::optional<SE3d> T = estimator->Localize(buffer[f - from], guess);
      r.T_w_c = T.value_or(guess);
      r.has_pose = T.has_value();
      r.source =
          T ? MonocularPoseSource::kLocalizedBeforeWindow : MonocularPoseSource::kNotLocalized;
      r.map = map;
    }
    for (int f = from; f <= b; ++f) Observe(f, buffer[f - from]);
    lost_in_a_row = 0;
    searching = false;
  }

  // Window AddFrame on frame i; after max_lost_frames lost in a row, a new start search begins
  // (the map is kept until a second frame arrives: at the end of the input, a single frame
  // left is tracked with it).
  void Track(int i, const FrameInput& frame, const window::StageObserver& observer) {
    FrameInput input = frame;
    // The first frame after the start: constant velocity of the frame before b (the window's
    // own prediction would repeat the whole a-b motion).
    if (i == b + 1 && b - 1 > a && records[b - 1].has_pose)
      input.T_w_c_guess = pose(b) * (pose(b - 1).Inverse() * pose(b));
    const window::WindowFrameResult r = estimator->AddFrame(input, observer);
    const bool finite =
        r.T_w_c.translation().allFinite() && r.T_w_c.rotation().coeffs().allFinite();
    const bool ok = r.ok && finite;
    MonocularFrameRecord& rec = records[i];
    rec.T_w_c = finite ? r.T_w_c : records[std::max(i - 1, 0)].T_w_c;
    rec.has_pose = ok;
    rec.source = ok ? MonocularPoseSource::kTracked : MonocularPoseSource::kLost;
    rec.keyframe = r.keyframe;
    rec.map = static_cast<int>(maps.size()) - 1;
    rec.window = r;
    summary.keyframes += r.keyframe;
    summary.lost_frames += !ok;
    summary.pnp_recoveries += r.pnp_fallback && ok;
    summary.marginalized_keyframes += r.marginalized_keyframes;
    summary.failed_marginalizations += r.marginalization_failed;
    ++summary.window_frames;
    lost_in_a_row = ok ? 0 : lost_in_a_row + 1;
    Observe(i, frame);
    if (lost_in_a_row >= options.max_lost_frames) {
      searching = true;
      from = next_first = i + 1;
      buffer.clear();
      message = "no frame pair";
    }
  }

  // After a start at frame i: the buffered frames after b tracked (or buffered again when the
  // tracking lost the map meanwhile).
  void CatchUp(const window::StageObserver& observer) {
    std::vector<FrameInput> rest(buffer.begin() + (b + 1 - from), buffer.end());
    buffer.clear();
    for (std::size_t k = 0; k < rest.size(); ++k) {
      const int f = b + 1 + static_cast<int>(k);
      if (searching)
        buffer.push_back(std::move(rest[k]));
      else
        Track(f, rest[k], observer);
    }
  }

  // Stereo (window.T_c0_c1): a start is one frame's left-right pairs (metric; no two-view
  // search), tried on each buffered frame in turn, put where the previous map's motion leads.
  void StereoSearch(const window::StageObserver& observer) {
    while (searching && next_first <= last()) {
      const int i = next_first;
      estimator.reset();
      auto map = std::make_unique<SlidingWindowEstimator>(K, options.window);
      const window::InitializationResult init =
          map->InitializeStereo(buffer[i - from], Where(i).T_w_a, options.min_stereo_landmarks);
      if (!init.ok) {
        message = "frame " + std::to_string(i) + ": " + std::to_string(init.points + init.lines) +
                  " landmarks from its left-right pairs (fewer than " +
                  std::to_string(options.min_stereo_landmarks) + ")";
        ++next_first;
        continue;
      }
      MonocularStart start;
      start.estimator = std::move(map);
      start.keyframes = {0};
      start.init = init;
      Begin(std::move(start), i);
      maps.back().stereo = true;
      CatchUp(observer);
    }
  }

  // The start search as far as the frames buffered allow (all of them at the end of the input),
  // then the catch-up of the frames after b.
  void Search(bool final, const window::StageObserver& observer) {
    if (options.window.T_c0_c1) {
      StereoSearch(observer);
      return;
    }
    while (searching) {
      const int n = static_cast<int>(buffer.size());
      if (final && n <= 1 && estimator) {  // a loss at one of the last two frames: no new start
        if (n == 1) Track(from, buffer[0], observer);
        searching = false;
        return;
      }
      const int i = next_first;
      if (i + 1 > last()) return;
      if (n >= 2) estimator.reset();  // the new start is certain: the old map is done
      const FrameSpan span{buffer.data() + (i - from), last() - i + 1};
      if (!search.Advance(K, options.window, options.start, span, Where(i), final, &message))
        return;
      std::optional<MonocularStart> start = search.Take();
      if (!start) {
        ++next_first;
        continue;
      }
      Begin(std::move(*start), i);
      CatchUp(observer);
    }
  }

  void Fail() {
    if (maps.empty()) {
      start_failure = message;
      return;
    }
    restart_failure = message;
    restart_failed_after = from - 1;
    for (int i = from; i <= last(); ++i) records[i].T_w_c = records[std::max(from - 1, 0)].T_w_c;
  }
};

MonocularOdometry::MonocularOdometry(const PinholeIntrinsics& K,
                                     const MonocularOdometryOptions& options)
    : impl_(std::make_unique<Impl>()) {
  options.Check();
  impl_->K = K;
  impl_->options = options;
}

MonocularOdometry::MonocularOdometry(const sensor::Camera& camera,
                                     const MonocularOdometryOptions& options)
    : MonocularOdometry(camera.K, options) {
  if (camera.IsPinhole()) return;
  impl_->undistorter = std::make_unique<vision::Undistorter>(camera);
  impl_->K = impl_->undistorter->ideal_camera().K;
}

MonocularOdometry::~MonocularOdometry() = default;

MonocularFrameResult MonocularOdometry::AddImage(double t, const cv::Mat& gray,
                                                 const vision::FrontendObserver& frontend_observer,
                                                 const window::StageObserver& window_observer) {
  FrameInput frame;
  frame.time = t;
  if (!gray.empty()) {
    Impl& m = *impl_;
    if (!m.frontend) {
      vision::ImageFrontendOptions options = m.options.frontend;
      options.use_lines = options.use_lines && m.options.window.use_lines;
      m.frontend = std::make_unique<vision::ImageFrontend>(m.K, options);
    }
    vision::ImageFrontendFrame f = m.frontend->Process(
        m.undistorter ? m.undistorter->Undistort(gray) : gray, frontend_observer);
    frame.points = std::move(f.points);
    frame.segments = std::move(f.segments);
  }
  return AddFrame(std::move(frame), window_observer);
}

MonocularFrameResult MonocularOdometry::AddFrame(FrameInput frame,
                                                 const window::StageObserver& window_observer) {
  Impl& m = *impl_;
  const int k = static_cast<int>(m.records.size());
  MonocularFrameResult result;
  result.frame = k;
  result.time = frame.time;
  result.observed_points = static_cast<int>(frame.points.size());
  result.observed_segments = static_cast<int>(frame.segments.size());
  m.records.emplace_back();
  m.records.back().time = frame.time;
  if (k > 0) m.records.back().T_w_c = m.records[k - 1].T_w_c;
  ++m.summary.frames;
  const std::size_t maps_before = m.maps.size();
  const int window_frames_before = m.summary.window_frames;
  if (m.searching) {
    m.buffer.push_back(std::move(frame));
    m.Search(false, window_observer);
  } else {
    m.Track(k, frame, window_observer);
  }
  const MonocularFrameRecord& r = m.records[k];
  result.has_pose = r.has_pose;
  result.T_w_c = r.T_w_c;
  if (r.source == MonocularPoseSource::kTracked || r.source == MonocularPoseSource::kLost) {
    result.window = r.window;
    result.caught_up_frames = m.summary.window_frames - window_frames_before - 1;
  }
  if (r.source == MonocularPoseSource::kLost)
    result.status = MonocularStatus::kLost;
  else if (m.maps.size() > maps_before)
    result.status =
        m.maps.size() == 1 ? MonocularStatus::kInitialized : MonocularStatus::kReinitialized;
  else if (r.source == MonocularPoseSource::kTracked)
    result.status = MonocularStatus::kTracking;
  return result;
}

void MonocularOdometry::Finish(const window::StageObserver& window_observer) {
  impl_->Search(true, window_observer);
  if (impl_->searching) impl_->Fail();
}

void MonocularOdometry::SetFrameObserver(MonocularFrameObserver observer) {
  impl_->frame_observer = std::move(observer);
}
const std::vector<MonocularFrameRecord>& MonocularOdometry::Trajectory() const {
  return impl_->records;
}
const std::vector<MonocularMap>& MonocularOdometry::Maps() const { return impl_->maps; }
const MonocularSummary& MonocularOdometry::Summary() const { return impl_->summary; }
const std::string& MonocularOdometry::StartFailure() const { return impl_->start_failure; }
const std::string& MonocularOdometry::RestartFailure() const { return impl_->restart_failure; }
int MonocularOdometry::RestartFailedAfter() const { return impl_->restart_failed_after; }
const PinholeIntrinsics& MonocularOdometry::K() const { return impl_->K; }
const vision::Undistorter* MonocularOdometry::undistorter() const {
  return impl_->undistorter.get();
}
const window::SlidingWindowEstimator* MonocularOdometry::map() const {
  return impl_->estimator.get();
}

}  // namespace odometry
}  // namespace plucker
