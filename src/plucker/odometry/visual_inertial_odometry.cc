#include "plucker/odometry/visual_inertial_odometry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "plucker/odometry/visual_inertial_initializer.h"
#include "plucker/odometry/visual_inertial_start_ba.h"
#include "plucker/vision/undistort.h"

namespace plucker {
namespace odometry {

const char* const kRefinedTrajectoryNote =
    "refined: T_w_b of every frame with a pose, the frames before the window's start "
    "backfilled when it started (docs/vio.md)";
const char* const kOnlineTrajectoryNote =
    "online: T_w_b as returned for each frame when it was given, none before the start "
    "(docs/vio.md)";

std::string VisualInertialOdometryOptions::Problem() const {
  if (window < 2 || iterations < 1 || min_line_views < 2 || !(two_view_line_sigma_scale >= 1.0) ||
      !(line_sigma_scale > 0.0) || !std::isfinite(line_sigma_scale) ||
      !(init_two_view_line_sigma_scale == 0.0 || init_two_view_line_sigma_scale >= 1.0) ||
      init_min_keyframes < 4 || init_max_keyframes < init_min_keyframes ||
      !(max_imu_factor_span_s > 0.0) || !(gyro_bias_prior_sigma > 0.0) ||
      !(accel_bias_prior_sigma > 0.0) || !(velocity_prior_sigma > 0.0) ||
      !(init_max_rotation_disagreement_deg > 0.0) || !(init_gyro_bias_bound >= 0.0) ||
      init_pair_budget < 0 || !(init_pair_min_rotated_parallax_px >= 0.0) ||
      !(two_view_min_plane_angle_px >= 0.0) || !(image_still_span_s >= 0.0) ||
      init_ba_iterations < 0 || init_extend_keyframes < 0 ||
      !(init_extend_min_rotation_deg >= 0.0) || !(init_extend_max_seconds >= 0.0) ||
      !(init_ba_accel_bias_prior_sigma > 0.0) || !(init_ba_velocity_prior_sigma > 0.0) ||
      !(keyframe_max_rotation_deg >= 0.0) || !(keyframe_min_turn_rate_deg_s >= 0.0) ||
      !(init_min_span_s >= 0.0) || !(init_keyframe_max_rotation_deg >= 0.0) ||
      !(tracking_velocity_sigma >= 0.0) || max_point_tracks < 1 ||
      !(point_min_distance_px >= 0.0) ||
      !(point_detect_below_share > 0.0 && point_detect_below_share <= 1.0) ||
      line_max_segments < 0 || !(line_detection_scale > 0.0 && line_detection_scale <= 1.0) ||
      line_flow_samples < 0 || line_flow_samples > 1000 ||
      (init_accel_bias && !init_accel_bias->allFinite()) ||
      (init_gyro_bias && !init_gyro_bias->allFinite())) {
    return "an option is out of range (window >= 2, min_line_views >= 2, "
           "two_view_line_sigma_scale >= 1, line_sigma_scale > 0, "
           "init_two_view_line_sigma_scale 0 or >= 1, "
           "init_min_keyframes >= 4, "
           "init_max_keyframes >= init_min_keyframes, sigmas and intervals > 0, "
           "tracking_velocity_sigma >= 0, "
           "init_ba_iterations >= 0, init_pair_budget >= 0, two_view_min_plane_angle_px >= 0, "
           "init_pair_min_rotated_parallax_px >= 0, point_min_distance_px >= 0, "
           "0 < point_detect_below_share "
           "<= 1, 0 < line_detection_scale <= 1, line_flow_samples in "
           "[0, 1000], init_accel_bias and init_gyro_bias finite)";
  }
  if (!(extrinsic_rotation_sigma > 0.0) || !(extrinsic_translation_sigma > 0.0) ||
      !(extrinsic_min_rotation_deg >= 0.0)) {
    return "extrinsic_rotation_sigma and extrinsic_translation_sigma must be > 0, "
           "extrinsic_min_rotation_deg >= 0";
  }
  if (!std::isfinite(time_offset_s) || !(std::abs(time_offset_s) < 1.0) ||
      !(time_offset_prior_sigma_s > 0.0)) {
    return "time_offset_s must be finite and within (-1, 1) s, time_offset_prior_sigma_s > 0";
  }
  return "";
}

void VisualInertialOdometryOptions::Check() const {
  const std::string problem = Problem();
  if (!problem.empty()) throw std::invalid_argument("VisualInertialOdometry: " + problem);
}

const char* ToString(VioStatus status) {
  switch (status) {
    case VioStatus::kInitializing:
      return "initializing";
    case VioStatus::kStarted:
      return "started";
    case VioStatus::kTracking:
      return "tracked";
    case VioStatus::kImuOnly:
      return "imu_only";
    case VioStatus::kStationary:
      return "stationary";
    case VioStatus::kSkippedNoImu:
      return "skipped_no_imu";
    case VioStatus::kSkippedNonFinite:
      return "skipped_non_finite";
    case VioStatus::kFailed:
      return "failed";
  }
  return "unknown";
}

std::string ToString(const VioFrameRecord& r) {
  switch (r.kind) {
    case VioFrameKind::kBeforeInitialization:
      return "before_initialization";
    case VioFrameKind::kInitialization:
      return "initialization";
    case VioFrameKind::kLocalizedBeforeWindow:
      return "localized_before_window";
    case VioFrameKind::kWindow:
      return ToString(r.status);
  }
  return "unknown";
}

window::SlidingWindowOptions WindowOptions(const VisualInertialOdometryOptions& c,
                                           const VisualInertialCalibration& calib) {
  window::SlidingWindowOptions o;
  o.window_size = c.window;
  o.max_iterations = c.iterations;
  o.use_lines = c.use_lines;
  o.prior_blocks = c.prior_on_poses_only ? window::SlidingWindowOptions::PriorBlocks::kPoses
                                         : window::SlidingWindowOptions::PriorBlocks::kLandmarks;
  o.retire_marginalized_tracks = false;  // features folders: ids are scene ids, revisited
  o.keyframe_parallax_px = c.keyframe_parallax_px;
  o.min_tracked = c.min_tracked;
  o.min_tracked_ratio = c.min_tracked_ratio;
  o.keyframe_max_rotation_deg = c.keyframe_max_rotation_deg;
  o.keyframe_min_turn_rate_deg_s = c.keyframe_min_turn_rate_deg_s;
  o.min_line_views = c.min_line_views;
  o.two_view_line_sigma_scale = c.two_view_line_sigma_scale;
  o.recheck_two_view_lines = c.recheck_two_view_lines;
  o.two_view_min_plane_angle_px = c.two_view_min_plane_angle_px;
  o.point_sigma_px = o.line_sigma_px = std::max(calib.pixel_sigma, 0.5);
  o.line_sigma_px *= c.line_sigma_scale;
  o.keep_marginalized_lines = c.keep_marginalized_lines;
  window::InertialOptions inertial;
  inertial.T_b_c = calib.T_b_c;
  inertial.imu = calib.imu;
  inertial.gravity_w = Eigen::Vector3d(0.0, 0.0, -calib.gravity_magnitude);
  inertial.gyro_bias_prior_sigma = c.gyro_bias_prior_sigma;
  inertial.accel_bias_prior_sigma = c.accel_bias_prior_sigma;
  inertial.velocity_prior_sigma = c.velocity_prior_sigma;
  inertial.tracking_velocity_sigma = c.tracking_velocity_sigma;
  inertial.max_imu_factor_span_s = c.max_imu_factor_span_s;
  inertial.estimate_extrinsic = c.estimate_extrinsic;
  inertial.extrinsic_rotation_sigma = c.extrinsic_rotation_sigma;
  inertial.extrinsic_translation_sigma = c.extrinsic_translation_sigma;
  inertial.extrinsic_min_rotation_deg = c.extrinsic_min_rotation_deg;
  inertial.estimate_time_offset = c.estimate_time_offset;
  inertial.time_offset_s = c.time_offset_s;
  inertial.time_offset_prior_sigma_s = c.time_offset_prior_sigma_s;
  o.inertial = inertial;
  return o;
}

vision::ImageFrontendOptions FrontendOptions(const VisualInertialOdometryOptions& c) {
  vision::ImageFrontendOptions o;
  o.use_lines = c.use_lines;
  o.points.target_count = c.max_point_tracks;
  o.points.min_distance_px = c.point_min_distance_px;
  o.points.detect_below_share = c.point_detect_below_share;
  o.max_segments = c.line_max_segments;
  o.detection_scale = c.line_detection_scale;
  o.lines.flow_samples = c.line_flow_samples;
  return o;
}

struct VisualInertialOdometry::Impl {
  VisualInertialOdometryOptions o;
  VisualInertialCalibration calib;
  VisualInertialInitializer initializer;
  VioInitialization init_info;
  std::unique_ptr<window::SlidingWindowEstimator> estimator;
  bool failed = false;
  std::string failure;
  // Until the start: every frame and sample (the initialisation's buffer), the image motion.
  std::vector<window::FrameInput> frames;
  std::vector<sensor::ImuSample> imu;
  std::vector<inertial::ImageMotionFlag> flags;
  double last_imu_t = -1e300, last_frame_t = -1e300;
  int num_frames = 0;
  window::FrameInput last;  // the previous frame (image motion)
  bool has_last = false;
  std::vector<VioFrameRecord> trajectory;
  VioStatistics stats;
  bool stretch_open = false;                         // the newest IMU-only stretch goes on
  std::unique_ptr<vision::Undistorter> undistorter;  // AddImage
  std::unique_ptr<vision::ImageFrontend> frontend;
  FrameObserver frame_observer;

  Impl(const VisualInertialOdometryOptions& options, const VisualInertialCalibration& c)
      : o(options), calib(c), initializer(options, c) {}

  void SetStationary(window::FrameInput* frame);
  int Count(const VioFrameRecord& rec);
  VioFrameResult Initialize(bool end, const window::StageObserver& observer);
  void StartWindow();
  VioFrameRecord Track(int index, const window::FrameInput& frame,
                       const window::StageObserver& observer);
  void Observe(int index, const window::FrameInput& frame) const;
};

// The frame observer on a frame with a pose in the window's map.
void VisualInertialOdometry::Impl::Observe(int index, const window::FrameInput& frame) const {
  const std::optional<SE3d>& T_w_b = trajectory[index].T_w_b;
  if (frame_observer && estimator && T_w_b) {
    frame_observer(index, frame, *T_w_b * estimator->ExtrinsicEstimate(), *estimator);
  }
}

// The window's zero-motion flag: no image motion against the previous frame (the first frame
// takes the second's). Until the start, the static test's flags: the image motion against the
// newest earlier frame at least image_still_span_s older (the oldest while there is none), so
// that a slow start at a high frame rate is seen moving as it is at 10 Hz.
void VisualInertialOdometry::Impl::SetStationary(window::FrameInput* frame) {
  frame->stationary = false;
  if (!has_last) return;
  const std::optional<inertial::ImageMotionFlag> flag = ImageMotion(last, *frame, o.image_still_px);
  if (flag) frame->stationary = flag->still;
  if (!estimator && !frames.empty()) {
    const double t_ref = frame->time - o.image_still_span_s + 1e-9;
    auto ref = frames.rbegin();
    while (ref + 1 != frames.rend() && ref->time > t_ref) ++ref;
    const std::optional<inertial::ImageMotionFlag> span_flag =
        ImageMotion(*ref, *frame, o.image_still_px);
    if (span_flag) flags.push_back(*span_flag);
  }
  if (num_frames == 1 && !frames.empty()) frames.front().stationary = frame->stationary;
}

// A settled frame into the statistics; returns the IMU-only frames in a row up to it.
int VisualInertialOdometry::Impl::Count(const VioFrameRecord& rec) {
  ++stats.settled_frames;
  if (rec.kind != VioFrameKind::kWindow) return 0;
  const bool skipped =
      rec.status == VioStatus::kSkippedNoImu || rec.status == VioStatus::kSkippedNonFinite;
  stats.skipped_frames += skipped;
  if (skipped) return 0;  // neither ends nor extends a stretch
  ++stats.window_frames;
  stats.stationary_frames += rec.status == VioStatus::kStationary;
  if (rec.status != VioStatus::kImuOnly) {
    stats.tracked_frames += rec.status == VioStatus::kTracking;
    stretch_open = false;
    return 0;
  }
  ++stats.imu_only_frames;
  std::vector<VioImuOnlyStretch>& s = stats.imu_only_stretches;
  if (!stretch_open) s.push_back({rec.frame, rec.frame, rec.time, rec.time});
  stretch_open = true;
  s.back().last = rec.frame;
  s.back().t_last = rec.time;
  return s.back().frames();
}

// The frame's outcome in the window.
VioFrameRecord VisualInertialOdometry::Impl::Track(int index, const window::FrameInput& frame,
                                                   const window::StageObserver& observer) {
  VioFrameRecord rec;
  rec.frame = index;
  rec.time = frame.time;
  rec.kind = VioFrameKind::kWindow;
  window::WindowFrameResult r;
  try {
    r = estimator->AddFrame(frame, observer);
  } catch (const std::invalid_argument& e) {  // the IMU does not cover the frame
    rec.status = VioStatus::kSkippedNoImu;
    rec.skip_reason = e.what();
    return rec;
  }
  const SE3d& T = r.state.T_w_b;
  if (!T.translation().allFinite() || !T.rotation().coeffs().allFinite()) {
    rec.status = VioStatus::kSkippedNonFinite;
    return rec;
  }
  rec.T_w_b = T;
  rec.status = r.imu_only ? (r.stationary ? VioStatus::kStationary : VioStatus::kImuOnly)
                          : VioStatus::kTracking;
  rec.keyframe = r.keyframe;
  rec.window = r;
  return rec;
}

// The window starts on the initialisation's keyframes; the poses of the frames up to its start.
void VisualInertialOdometry::Impl::StartWindow() {
  VioStart start = initializer.start();
  const int n = static_cast<int>(frames.size());
  if (start.method == "dynamic" && o.init_ba_iterations > 0)
    init_info.adjustment = AdjustDynamicStart(o, calib, frames, imu, &start);
  estimator =
      std::make_unique<window::SlidingWindowEstimator>(calib.camera.K, WindowOptions(o, calib));
  estimator->AddImu(imu);
  // Dynamic: the window starts with the aligned keyframes (the newest `window` of them), else
  // (too few landmarks) with the earliest of them that shares enough landmarks with the newest.
  std::vector<int> start_keyframes;
  window::InitializationResult init;
  if (start.method == "dynamic") {
    std::vector<window::FrameInput> kf_frames;
    std::vector<sensor::BodyState> states;
    const int first = std::max(0, static_cast<int>(start.candidates.size()) + 1 - o.window);
    for (int k = first; k < static_cast<int>(start.candidates.size()); ++k) {
      start_keyframes.push_back(start.candidates[k]);
      kf_frames.push_back(frames[start.candidates[k]]);
      states.push_back(start.candidate_states[k]);
    }
    start_keyframes.push_back(start.second);
    kf_frames.push_back(frames[start.second]);
    states.push_back(start.state_second);
    init = estimator->InitializeInertial(kf_frames, states, 10);
    if (init.ok) {
      start.first = start_keyframes.front();
      start.state_first = states.front();
    }
  }
  if (!init.ok) {
    init =
        estimator->InitializeInertial(frames[start.first], start.state_first, frames[start.second],
                                      start.state_second, start.method == "static" ? 0 : 10);
  }
  for (std::size_t k = 1; !init.ok && k < start.candidates.size(); ++k) {
    start.first = start.candidates[k];
    start.state_first = start.candidate_states[k];
    init = estimator->InitializeInertial(frames[start.first], start.state_first,
                                         frames[start.second], start.state_second, 10);
  }
  init_info.done = true;
  init_info.method = start.method;
  init_info.first = start.first;
  init_info.second = start.second;
  init_info.state_first = start.state_first;
  if (!init.ok) {
    failed = true;
    failure = "the " + start.method +
              " initialisation succeeded but the window could not start (too few landmarks "
              "triangulated)";
    estimator.reset();
    return;
  }
  // Frames up to the window's start: the initialisation's poses (the window's own for its two).
  for (int f = 0; f <= start.second && f < n; ++f) {
    VioFrameRecord& rec = trajectory[f];
    if (f < static_cast<int>(start.T_w_b.size()) && start.T_w_b[f]) rec.T_w_b = start.T_w_b[f];
    rec.kind = rec.T_w_b ? VioFrameKind::kInitialization : VioFrameKind::kBeforeInitialization;
  }
  const std::vector<sensor::BodyState> first_states = estimator->KeyframeStates();
  if (first_states.size() != start_keyframes.size() || start_keyframes.front() != start.first)
    start_keyframes = {start.first, start.second};
  for (std::size_t k = 0; k < start_keyframes.size(); ++k) {
    trajectory[start_keyframes[k]].T_w_b = first_states[k].T_w_b;
    trajectory[start_keyframes[k]].keyframe = true;
  }
  const SE3d T_c_b = calib.T_b_c.Inverse();
  // Frames between the window's first keyframes: localized against its map (the aligned visual
  // poses carry the alignment's scale error), from the aligned pose of the frame.
  for (std::size_t k = 0; start.method == "dynamic" && k + 1 < start_keyframes.size(); ++k) {
    for (int f = start_keyframes[k] + 1; f < start_keyframes[k + 1]; ++f) {
      std::optional<SE3d>& T_w_b = trajectory[f].T_w_b;
      if (!T_w_b) continue;
      const std::optional<SE3d> T_w_c = estimator->Localize(frames[f], *T_w_b * calib.T_b_c);
      if (T_w_c) T_w_b = *T_w_c * T_c_b;
    }
  }
  // Frames before the initialisation without a pose: localized against the first map (motion-
  // only), else the next frame's pose (the body taken as where it started).
  for (int f = start.first - 1; f >= 0; --f) {
    if (trajectory[f].T_w_b) continue;
    const SE3d& next = *trajectory[f + 1].T_w_b;
    const std::optional<SE3d> T_w_c = estimator->Localize(frames[f], next * calib.T_b_c);
    trajectory[f].T_w_b = T_w_c ? *T_w_c * T_c_b : next;
    if (T_w_c) trajectory[f].kind = VioFrameKind::kLocalizedBeforeWindow;
  }
}

// Advances the initialisation on the buffer; at the start, the window runs on the frames after
// its second keyframe and the buffer is released.
VioFrameResult VisualInertialOdometry::Impl::Initialize(bool end,
                                                        const window::StageObserver& observer) {
  VioFrameResult result;
  result.frame = num_frames - 1;
  result.time = frames.empty() ? 0.0 : frames.back().time;
  if (!initializer.Advance(frames, imu, flags, end)) {
    if (initializer.failed()) {
      result.status = VioStatus::kFailed;
      result.message =
          "cannot initialise: the log does not start still and no visual-inertial alignment "
          "succeeded (too little parallax or IMU excitation)";
      failed = true;
      failure = result.message;
      init_info.events = initializer.events();
    }
    return result;
  }
  init_info.events = initializer.events();
  StartWindow();
  if (failed) {
    result.status = VioStatus::kFailed;
    result.message = failure;
    return result;
  }
  const int second = initializer.start().second;
  for (int f = 0; f <= second && f < static_cast<int>(frames.size()); ++f) Observe(f, frames[f]);
  for (int f = second + 1; f < static_cast<int>(frames.size()); ++f) {
    trajectory[f] = Track(f, frames[f], observer);
    Observe(f, frames[f]);
  }
  for (int f = 0; f < static_cast<int>(frames.size()); ++f) {
    result.settled.push_back(trajectory[f]);
    result.imu_only_run = Count(trajectory[f]);
  }
  for (VioFrameRecord& rec : trajectory) rec.window.reset();  // kept in `settled` only
  const VioFrameRecord& last = result.settled.back();
  result.status = last.kind == VioFrameKind::kWindow ? last.status : VioStatus::kStarted;
  result.T_w_b = last.T_w_b;
  result.window = last.window;
  if (last.window) {
    result.v_w = last.window->state.v_w;
    result.bias = last.window->state.bias;
  } else {
    const std::vector<sensor::BodyState> states = estimator->KeyframeStates();
    result.v_w = states.back().v_w;
    result.bias = states.back().bias;
  }
  frames.clear();
  frames.shrink_to_fit();
  imu.clear();
  imu.shrink_to_fit();
  flags.clear();
  return result;
}

VisualInertialOdometry::VisualInertialOdometry(const VisualInertialOdometryOptions& options,
                                               const VisualInertialCalibration& calibration) {
  options.Check();
  impl_ = std::make_unique<Impl>(options, calibration);
}

VisualInertialOdometry::~VisualInertialOdometry() = default;

void VisualInertialOdometry::AddImu(const sensor::ImuSample& sample) {
  Impl& m = *impl_;
  if (!(sample.t > m.last_imu_t) || !sample.gyro.allFinite() || !sample.accel.allFinite()) {
    throw std::invalid_argument(
        "VisualInertialOdometry::AddImu: IMU samples must be finite with increasing times");
  }
  m.last_imu_t = sample.t;
  if (m.estimator) {
    m.estimator->AddImu({sample});
  } else if (!m.failed) {
    m.imu.push_back(sample);
  }
}

VioFrameResult VisualInertialOdometry::AddImage(double t, const cv::Mat& image,
                                                const vision::FrontendObserver& frontend_observer,
                                                const window::StageObserver& window_observer) {
  Impl& m = *impl_;
  if (!m.undistorter) {
    m.undistorter = std::make_unique<vision::Undistorter>(m.calib.camera);
    m.frontend = std::make_unique<vision::ImageFrontend>(m.undistorter->ideal_camera().K,
                                                         FrontendOptions(m.o));
  }
  if (!(t > m.last_frame_t)) {
    throw std::invalid_argument("VisualInertialOdometry::AddImage: times must increase");
  }
  const cv::Mat undistorted = m.undistorter->Undistort(image);  // throws for a wrong size
  const vision::ImageFrontendFrame f = m.frontend->Process(undistorted, frontend_observer);
  window::FrameInput frame;
  frame.time = t;
  frame.points = f.points;
  frame.segments = f.segments;
  return AddFrame(frame, window_observer);
}

VioFrameResult VisualInertialOdometry::AddFrame(const window::FrameInput& input,
                                                const window::StageObserver& observer) {
  Impl& m = *impl_;
  if (!(input.time > m.last_frame_t)) {
    throw std::invalid_argument("VisualInertialOdometry::AddFrame: times must increase");
  }
  m.last_frame_t = input.time;
  window::FrameInput frame = input;
  m.SetStationary(&frame);
  m.last = frame;
  m.has_last = true;
  const int index = m.num_frames++;
  VioFrameRecord record;
  record.frame = index;
  record.time = frame.time;
  m.trajectory.push_back(record);
  VioFrameResult result;
  if (m.failed) {
    result.frame = index;
    result.time = frame.time;
    result.status = VioStatus::kFailed;
    result.message = m.failure;
  } else if (m.estimator) {
    const VioFrameRecord r = m.Track(index, frame, observer);
    m.trajectory[index] = r;
    m.Observe(index, frame);
    m.trajectory[index].window.reset();
    result.frame = index;
    result.time = frame.time;
    result.status = r.status;
    result.T_w_b = r.T_w_b;
    result.window = r.window;
    if (r.window) {
      result.v_w = r.window->state.v_w;
      result.bias = r.window->state.bias;
    }
    result.settled.push_back(r);
    result.imu_only_run = m.Count(r);
  } else {
    m.frames.push_back(std::move(frame));
    result = m.Initialize(false, observer);
  }
  result.observed_points = static_cast<int>(input.points.size());
  result.observed_segments = static_cast<int>(input.segments.size());
  return result;
}

VioFrameResult VisualInertialOdometry::Finish(const window::StageObserver& observer) {
  Impl& m = *impl_;
  VioFrameResult result;
  result.frame = m.num_frames - 1;
  if (m.failed) {
    result.status = VioStatus::kFailed;
    result.message = m.failure;
  }
  if (m.estimator || m.failed || m.frames.empty()) return result;
  return m.Initialize(true, observer);
}

void VisualInertialOdometry::SetFrameObserver(FrameObserver observer) {
  impl_->frame_observer = std::move(observer);
}
const vision::Undistorter* VisualInertialOdometry::undistorter() const {
  return impl_->undistorter.get();
}
const PinholeIntrinsics& VisualInertialOdometry::K() const { return impl_->calib.camera.K; }

bool VisualInertialOdometry::initialized() const { return impl_->estimator != nullptr; }
const VioInitialization& VisualInertialOdometry::initialization() const { return impl_->init_info; }
const std::vector<VioFrameRecord>& VisualInertialOdometry::RefinedTrajectory() const {
  return impl_->trajectory;
}
const VioStatistics& VisualInertialOdometry::statistics() const { return impl_->stats; }

double VioStatistics::ImuOnlyShare() const {
  return window_frames > 0 ? static_cast<double>(imu_only_frames) / window_frames : 0.0;
}

SE3d VisualInertialOdometry::ExtrinsicEstimate() const {
  return impl_->estimator ? impl_->estimator->ExtrinsicEstimate() : impl_->calib.T_b_c;
}
bool VisualInertialOdometry::ExtrinsicFree() const {
  return impl_->estimator && impl_->estimator->ExtrinsicFree();
}
double VisualInertialOdometry::TimeOffsetEstimate() const {
  return impl_->estimator ? impl_->estimator->TimeOffsetEstimate() : impl_->o.time_offset_s;
}

}  // namespace odometry
}  // namespace plucker
