// The estimator's entry points: construction (options checked, the marginalization strategy
// chosen), AddFrame as the algorithm of the header's file comment, Localize and the state's
// accessors. The steps live in the files listed in window_internal.h.
#include "plucker/window/sliding_window_estimator.h"

#include <ceres/loss_function.h>

#include <cmath>
#include <stdexcept>

#include "plucker/geometry/orthonormal_line.h"
#include "plucker/window/window_internal.h"

namespace plucker {
namespace window {

using internal::Frame;

SlidingWindowEstimator::SlidingWindowEstimator(const PinholeIntrinsics& K,
                                               const SlidingWindowOptions& options)
    : impl_(std::make_unique<Impl>()) {
  if (!K.IsValid()) throw std::invalid_argument("SlidingWindowEstimator: invalid intrinsics");
  if (options.window_size < 2)
    throw std::invalid_argument("SlidingWindowEstimator: window_size < 2");
  if (!(options.point_sigma_px > 0.0) || !(options.line_sigma_px > 0.0) ||
      !(options.loss_scale > 0.0))
    throw std::invalid_argument("SlidingWindowEstimator: sigmas and loss scale must be positive");
  if (!(options.max_keyframe_interval_s >= 0.0))
    throw std::invalid_argument("SlidingWindowEstimator: max_keyframe_interval_s < 0");
  if (!(options.keyframe_max_rotation_deg >= 0.0))
    throw std::invalid_argument("SlidingWindowEstimator: keyframe_max_rotation_deg < 0");
  if (!(options.keyframe_min_turn_rate_deg_s >= 0.0))
    throw std::invalid_argument("SlidingWindowEstimator: keyframe_min_turn_rate_deg_s < 0");
  if (options.T_c0_c1 && options.inertial)
    throw std::invalid_argument("SlidingWindowEstimator: stereo is not for the inertial mode");
  if (!(options.start_scale_sigma >= 0.0) || !std::isfinite(options.start_scale_sigma))
    throw std::invalid_argument("SlidingWindowEstimator: start_scale_sigma < 0");
  if (options.min_line_views < 2 || !(options.max_new_line_rms_px >= 0.0))
    throw std::invalid_argument(
        "SlidingWindowEstimator: min_line_views < 2 or max_new_line_rms_px < 0");
  if (!(options.two_view_line_sigma_scale >= 1.0) ||
      !std::isfinite(options.two_view_line_sigma_scale))
    throw std::invalid_argument("SlidingWindowEstimator: two_view_line_sigma_scale < 1");
  if (!(options.two_view_min_plane_angle_px >= 0.0) ||
      !std::isfinite(options.two_view_min_plane_angle_px))
    throw std::invalid_argument("SlidingWindowEstimator: two_view_min_plane_angle_px < 0");
  impl_->K = K;
  impl_->opt = options;
  impl_->loss = factors::MakeLossFunction(options.loss, options.loss_scale);
  if (options.inertial && options.inertial->estimate_extrinsic &&
      !(options.inertial->extrinsic_rotation_sigma > 0.0 &&
        options.inertial->extrinsic_translation_sigma > 0.0 &&
        options.inertial->extrinsic_min_rotation_deg >= 0.0)) {
    throw std::invalid_argument(
        "SlidingWindowEstimator: the extrinsic sigmas must be positive and "
        "extrinsic_min_rotation_deg >= 0");
  }
  if (options.inertial && options.inertial->estimate_time_offset &&
      !(std::isfinite(options.inertial->time_offset_s) &&
        options.inertial->time_offset_prior_sigma_s > 0.0 &&
        std::isfinite(options.inertial->time_offset_prior_sigma_s))) {
    throw std::invalid_argument(
        "SlidingWindowEstimator: time_offset_s must be finite and time_offset_prior_sigma_s "
        "positive");
  }
  if (options.inertial && !(options.inertial->tracking_velocity_sigma >= 0.0 &&
                            std::isfinite(options.inertial->tracking_velocity_sigma))) {
    throw std::invalid_argument("SlidingWindowEstimator: tracking_velocity_sigma must be >= 0");
  }
  impl_->marginalization = options.prior_blocks == SlidingWindowOptions::PriorBlocks::kPoses
                               ? internal::MakePosesOnlyPrior()
                               : internal::MakeLandmarkPrior();
  impl_->ResetExtrinsic();
  impl_->ResetTimeOffset();
}

SlidingWindowEstimator::~SlidingWindowEstimator() = default;

bool SlidingWindowEstimator::initialized() const { return !impl_->keyframes.empty(); }

// Predict, track, decide; a keyframe is then triangulated from, solved and the oldest keyframe
// marginalized (the file comment of sliding_window_estimator.h).
WindowFrameResult SlidingWindowEstimator::AddFrame(const FrameInput& input,
                                                   const StageObserver& observer) {
  Impl& m = *impl_;
  auto stage = [&observer](WindowStage s) {
    if (observer) observer(s);
  };
  WindowFrameResult result;
  if (m.keyframes.empty())
    throw std::logic_error("SlidingWindowEstimator::AddFrame before Initialize");
  // Predict (throws before any change when the IMU samples do not cover the frame).
  internal::Prediction prediction = m.PredictFrame(input);
  result.stationary = prediction.stationary;
  std::unique_ptr<Frame> frame = m.MakeFrame(input, prediction.T_w_c);
  m.RefineNewestKeyframeVelocities(frame->input);
  m.RememberObservations(frame->input);
  frame->input.stationary = result.stationary;
  // Track.
  stage(WindowStage::kTracking);
  const internal::TrackResult track =
      m.TrackFrame(frame.get(), input, prediction, &result.pnp_fallback);
  result.tracking_iterations = track.iterations;
  result.tracked_points = track.points;
  result.tracked_lines = track.lines;
  result.ok = track.ok;
  result.T_w_c = track.ok ? track.T_w_c : prediction.T_w_c;
  frame->SetCameraPose(result.T_w_c);
  // Decide.
  m.UpdateTurnRate(*frame);
  result.keyframe = m.DecideKeyframe(*frame, track, &result);
  if (result.keyframe) m.peak_turn_rate_deg_s = 0.0;
  if (m.opt.inertial) {
    result.imu_only = !track.ok;
    prediction.state.T_w_b = SE3d::FromParameters(frame->pose);
    result.state = prediction.state;
    frame->SetState(prediction.state);
    frame->imu_from_previous = std::move(prediction.imu);
  }
  if (result.keyframe) {
    m.keyframes.push_back(std::move(frame));
    // Triangulate.
    stage(WindowStage::kTriangulation);
    m.CountLineViews(*m.keyframes.back(), &result);
    m.Triangulate(*m.keyframes.back(), &result.new_points, &result.new_lines, &result);
    // Solve.
    stage(WindowStage::kSolve);
    m.SolveWindow(&result);
    result.T_w_c = m.keyframes.back()->T_w_c();
    if (m.opt.inertial) {
      result.state = m.keyframes.back()->State();
      result.imu_chi2 = m.NewestImuChi2();
    }
    // Marginalize.
    if (static_cast<int>(m.keyframes.size()) > m.opt.window_size) {
      stage(WindowStage::kMarginalization);
      m.marginalization->MarginalizeOldest(m, &result);
    }
    if (m.opt.inertial) m.PruneImu();
  }
  m.prev_T_w_c = m.last_T_w_c;
  m.last_T_w_c = result.T_w_c;
  m.last_time = input.time;
  result.extrinsic_free = m.extrinsic_free;
  m.FillCounts(&result);
  stage(WindowStage::kDone);
  return result;
}

// Truly const: MakeFrame and Track change only the local frame.
std::optional<SE3d> SlidingWindowEstimator::Localize(const FrameInput& input,
                                                     const SE3d& guess) const {
  const Impl& m = *impl_;
  if (m.keyframes.empty()) return std::nullopt;
  std::unique_ptr<Frame> frame = m.MakeFrame(input, guess);
  const internal::TrackResult track = m.Track(frame.get(), guess);
  if (!track.ok) return std::nullopt;
  return track.T_w_c;
}

std::vector<SE3d> SlidingWindowEstimator::KeyframePoses() const {
  std::vector<SE3d> out;
  for (const auto& f : impl_->keyframes) out.push_back(f->T_w_c());
  return out;
}

std::map<int, Eigen::Vector3d> SlidingWindowEstimator::Points() const {
  std::map<int, Eigen::Vector3d> out;
  for (const auto& [id, p] : impl_->points) out[id] = Eigen::Vector3d(p->p[0], p->p[1], p->p[2]);
  return out;
}

std::map<int, Line6d> SlidingWindowEstimator::Lines() const {
  std::map<int, Line6d> out;
  for (const auto& [id, l] : impl_->lines) {
    const Line6d L_a = PluckerFromOrthonormal(OrthonormalLine::FromParameters(l->block));
    const std::optional<Line6d> L_w = NormalizeLineDirection(WorldFromAnchored(L_a, l->anchor));
    if (L_w) out[id] = *L_w;
  }
  return out;
}

}  // namespace window
}  // namespace plucker
