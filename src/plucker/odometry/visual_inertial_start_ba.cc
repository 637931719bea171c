#include "plucker/odometry/visual_inertial_start_ba.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace plucker {
namespace odometry {
namespace {

// The gyro bias prior of the solve when init_gyro_bias is given (rad/s): held.
constexpr double kHeldGyroBiasSigma = 1e-4;

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

}  // namespace

StartAdjustmentSummary AdjustDynamicStart(const VisualInertialOdometryOptions& o,
                                          const VisualInertialCalibration& calib,
                                          const std::vector<window::FrameInput>& frames,
                                          const std::vector<sensor::ImuSample>& imu,
                                          VioStart* start) {
  StartAdjustmentSummary result;
  result.ran = true;
  std::vector<int> kf = start->candidates;
  kf.push_back(start->second);
  std::vector<sensor::BodyState> states = start->candidate_states;
  states.push_back(start->state_second);
  result.keyframes = static_cast<int>(kf.size());
  if (kf.size() < 3 || states.size() != kf.size()) return result;
  for (sensor::BodyState& s : states) {  // the diagnostic biases (docs/results/vio.md)
    if (o.init_accel_bias) s.bias.accel = *o.init_accel_bias;
    if (o.init_gyro_bias) s.bias.gyro = *o.init_gyro_bias;
  }
  std::vector<window::FrameInput> kf_frames;
  for (int k : kf) kf_frames.push_back(frames[k]);

  window::SlidingWindowOptions wo = WindowOptions(o, calib);
  wo.window_size = static_cast<int>(kf.size());
  wo.max_iterations = o.init_ba_iterations;
  wo.inertial->free_first_tilt = true;
  wo.inertial->accel_bias_prior_sigma = o.init_ba_accel_bias_prior_sigma;
  wo.inertial->velocity_prior_sigma = o.init_ba_velocity_prior_sigma;
  if (o.init_gyro_bias) wo.inertial->gyro_bias_prior_sigma = kHeldGyroBiasSigma;
  wo.inertial->estimate_extrinsic = false;
  wo.inertial->estimate_time_offset = false;
  window::SlidingWindowEstimator ba(calib.camera.K, wo);
  ba.AddImu(imu);
  const window::InitializationResult init = ba.InitializeInertial(kf_frames, states, 10);
  if (!init.ok) return result;
  const std::vector<sensor::BodyState> refined = ba.KeyframeStates();
  if (refined.size() != kf.size()) return result;
  result.ok = true;
  result.points = init.points;
  result.lines = init.lines;
  result.iterations = init.iterations;
  result.final_cost = init.final_cost;
  const Eigen::Vector3d up(0.0, 0.0, 1.0);
  result.tilt_change_deg = AngleDeg(states.back().T_w_b.rotation().inverse() * up,
                                    refined.back().T_w_b.rotation().inverse() * up);
  const double before =
      (states.back().T_w_b.translation() - states.front().T_w_b.translation()).norm();
  const double after =
      (refined.back().T_w_b.translation() - refined.front().T_w_b.translation()).norm();
  if (before > 0.0) result.scale_change = after / before;

  // The frames between the keyframes: their aligned pose carried onto the refined keyframe
  // before them, then localized against the solve's map.
  const SE3d T_c_b = calib.T_b_c.Inverse();
  for (std::size_t k = 0; k + 1 < kf.size(); ++k) {
    const SE3d T_before = states[k].T_w_b;
    for (int f = kf[k] + 1; f < kf[k + 1]; ++f) {
      if (f >= static_cast<int>(start->T_w_b.size()) || !start->T_w_b[f]) continue;
      const SE3d guess = refined[k].T_w_b * (T_before.Inverse() * *start->T_w_b[f]);
      const std::optional<SE3d> T_w_c = ba.Localize(frames[f], guess * calib.T_b_c);
      start->T_w_b[f] = T_w_c ? *T_w_c * T_c_b : guess;
    }
  }
  // The frames after the second keyframe (the initialisation's last frames): carried likewise.
  for (int f = kf.back() + 1; f < static_cast<int>(start->T_w_b.size()); ++f) {
    if (start->T_w_b[f])
      start->T_w_b[f] = refined.back().T_w_b * (states.back().T_w_b.Inverse() * *start->T_w_b[f]);
  }
  for (std::size_t k = 0; k < kf.size(); ++k) {
    if (kf[k] < static_cast<int>(start->T_w_b.size())) start->T_w_b[kf[k]] = refined[k].T_w_b;
  }
  for (std::size_t k = 0; k + 1 < kf.size(); ++k) start->candidate_states[k] = refined[k];
  start->state_first = refined.front();
  start->state_second = refined.back();
  return result;
}

}  // namespace odometry
}  // namespace plucker
