// Predict and track: the next frame's predicted pose, its motion-only refinement against the
// window's landmarks (frame_tracker.h) with outlier flagging, and the PnP RANSAC fallback.
#include <algorithm>
#include <cmath>
#include <limits>

#include "plucker/vision/pnp_ransac.h"
#include "plucker/window/frame_tracker.h"
#include "plucker/window/window_internal.h"

namespace plucker {
namespace window {

using internal::Frame;
using internal::Prediction;
using internal::TrackResult;

Prediction SlidingWindowEstimator::Impl::PredictFrame(const FrameInput& input) const {
  Prediction p;
  if (opt.inertial) {
    p.state = Predict(input.time, &p.imu);
    const sensor::BodyState kf = keyframes.back()->State();
    // Across an IMU gap, the predicted speed at its start (InertialOptions::imu_gap_s).
    double speed = p.state.v_w.norm();
    if (input.stationary) {
      const std::optional<double> gap = ImuGapStart(kf.t, input.time);
      std::unique_ptr<ImuPreintegration> to_gap;
      if (gap) speed = *gap > kf.t ? Predict(*gap, &to_gap).v_w.norm() : kf.v_w.norm();
    }
    p.stationary = BelievedStationary(input.stationary, kf.v_w) &&
                   speed < opt.inertial->stationary_max_predicted_speed;
    if (p.stationary) {  // the body stands: the newest keyframe's pose, zero velocity
      p.state.T_w_b = keyframes.back()->State().T_w_b;
      p.state.v_w.setZero();
    }
  }
  p.T_w_c = input.T_w_c_guess ? *input.T_w_c_guess
            : opt.inertial    ? p.state.T_w_b * T_b_c
                              : last_T_w_c * (prev_T_w_c.Inverse() * last_T_w_c);
  return p;
}

TrackResult SlidingWindowEstimator::Impl::TrackFrame(Frame* f, const FrameInput& input,
                                                     const Prediction& prediction,
                                                     bool* pnp_tried) const {
  std::unique_ptr<ceres::CostFunction> imu_prior;
  if (opt.inertial && opt.inertial->tracking_velocity_sigma > 0.0 && !input.T_w_c_guess) {
    imu_prior.reset(ImuPosePrior(prediction.state, *prediction.imu));
  }
  TrackResult track = Track(f, prediction.T_w_c, imu_prior.get());
  if (!track.ok && opt.pnp_fallback) {
    const std::optional<SE3d> pnp = PnpPose(*f);
    *pnp_tried = true;
    if (pnp) {
      std::fill(f->point_outlier.begin(), f->point_outlier.end(), 0);
      std::fill(f->segment_outlier.begin(), f->segment_outlier.end(), 0);
      track = Track(f, *pnp);
    }
  }
  return track;
}

// `prior` (optional): a pose-only term on the frame's pose block (ImuPosePrior).
TrackResult SlidingWindowEstimator::Impl::Track(Frame* f, const SE3d& guess,
                                                const ceres::CostFunction* prior) const {
  TrackResult result;
  result.T_w_c = guess;
  f->SetCameraPose(guess);
  // One term per observation of an existing landmark (outliers of earlier rounds left out).
  struct Observation {
    std::unique_ptr<ceres::CostFunction> cost;
    const double* landmark;
    int index;
    bool is_point;
  };
  std::vector<Observation> obs;
  for (std::size_t i = 0; i < f->input.points.size(); ++i) {
    const auto it = points.find(f->input.points[i].point_id);
    if (f->point_outlier[i] || it == points.end()) continue;
    obs.push_back({std::unique_ptr<ceres::CostFunction>(PointCost(f->input.points[i])),
                   it->second->p, static_cast<int>(i), true});
  }
  if (opt.use_lines) {
    for (std::size_t i = 0; i < f->input.segments.size(); ++i) {
      const auto it = lines.find(f->input.segments[i].line_id);
      if (f->segment_outlier[i] || it == lines.end()) continue;
      obs.push_back(
          {std::unique_ptr<ceres::CostFunction>(LineCost(f->input.segments[i], *it->second)),
           it->second->block, static_cast<int>(i), false});
    }
  }
  // Flags the observations that cannot be evaluated at the pose (behind the camera) or, with
  // `threshold`, whose whitened residual exceeds it; returns how many.
  const auto flag = [&](double threshold) {
    int flagged = 0;
    for (Observation& o : obs) {
      if (o.cost == nullptr) continue;
      double res[2];
      const double* params[2] = {f->pose, o.landmark};
      const bool ok =
          o.cost->Evaluate(params, res, nullptr) && std::isfinite(res[0]) && std::isfinite(res[1]);
      if (ok && std::hypot(res[0], res[1]) <= threshold) continue;
      (o.is_point ? f->point_outlier : f->segment_outlier)[o.index] = 1;
      o.cost.reset();
      ++flagged;
    }
    return flagged;
  };
  flag(std::numeric_limits<double>::infinity());
  PoseRefinementOptions ro;
  ro.max_iterations = opt.max_tracking_iterations;
  for (int round = 0; round < 2; ++round) {
    std::vector<PoseTerm> terms;
    for (const Observation& o : obs)
      if (o.cost) terms.push_back({o.cost.get(), o.landmark});
    if (terms.size() < 6) return result;
    if (prior) terms.push_back({prior, nullptr});
    result.iterations += RefinePose(terms, loss.get(), ro, f->pose).iterations;
    if (flag(opt.outlier_sigmas) == 0) break;
  }
  result.points = result.lines = 0;
  for (std::size_t i = 0; i < f->input.points.size(); ++i)
    if (!f->point_outlier[i] && points.count(f->input.points[i].point_id)) ++result.points;
  for (std::size_t i = 0; i < f->input.segments.size(); ++i)
    if (!f->segment_outlier[i] && lines.count(f->input.segments[i].line_id)) ++result.lines;
  result.T_w_c = f->T_w_c();
  result.ok = result.points + result.lines >= 6 && f->T_w_c().translation().allFinite();
  return result;
}

// The pose from PnP RANSAC of the frame's point tracks against the window's points, or nullopt.
std::optional<SE3d> SlidingWindowEstimator::Impl::PnpPose(const Frame& f) const {
  std::vector<Eigen::Vector3d> points_w;
  std::vector<Eigen::Vector2d> uv;
  for (const auto& p : f.input.points) {
    const auto it = points.find(p.point_id);
    if (it == points.end()) continue;
    points_w.emplace_back(it->second->p[0], it->second->p[1], it->second->p[2]);
    uv.push_back(p.uv);
  }
  vision::PnpRansacOptions pnp;
  pnp.solver = vision::PnpSolver::kEpnp;
  pnp.iterations = 200;
  pnp.threshold_px = opt.pnp_threshold_px;
  pnp.confidence = 0.999;
  pnp.min_correspondences = std::max(opt.pnp_min_inliers, 6);
  pnp.min_inliers = opt.pnp_min_inliers;
  const vision::PnpRansacResult r = vision::PnpRansac(points_w, uv, K, pnp);
  if (!r.ok()) return std::nullopt;
  return r.T_c_w.Inverse();
}

}  // namespace window
}  // namespace plucker
