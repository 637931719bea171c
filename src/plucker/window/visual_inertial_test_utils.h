// The visual-inertial window runs shared by visual_inertial_window_test.cc and
// visual_inertial_marginalization_test.cc (not installed): a simulated room, and the window
// started at its true states and fed the rest.
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/loss_function.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>

#include "plucker/eval/ate.h"
#include "plucker/factors/held_extrinsic_factor.h"
#include "plucker/factors/imu_factor.h"
#include "plucker/factors/marginalization.h"
#include "plucker/factors/point_reprojection_factor.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/sim/camera_observations.h"
#include "plucker/window/sliding_window_estimator.h"
#include "plucker/window/window_test_utils.h"

namespace plucker {
namespace window {
struct VioRun {
  std::vector<SE3d> gt, est;     // T_w_b per frame
  std::vector<int> keyframe_of;  // per frame: the newest keyframe when it was added (-1: start)
  int keyframes = 0, marginalized = 0, imu_only = 0, failed_marginalizations = 0;
  double max_error_m = 0.0;
  double mean_imu_chi2 = 0.0;
  double mean_nees = 0.0;
  int nees_count = 0;
  bool initialized = false;
  // Per keyframe (NEES runs): the newest pose moved so that the oldest keyframe is the true one,
  // its covariance, and the frame of the oldest keyframe.
  struct Relative {
    SE3d T_w_b;
    Eigen::Matrix<double, 6, 6> cov;
    int oldest = 0;
  };
  std::map<int, Relative> relative;
};

inline sim::CameraSimulation Simulate(int frames, bool noise, std::uint64_t seed) {
  sim::CameraSimulationOptions o;
  o.scene.kind = sim::SceneKind::kRoom;
  o.num_frames = frames;
  o.seed = seed;
  if (!noise) {
    o.obs.pixel_sigma = 0.0;
    o.imu.model.gyro_noise_density = 0.0;
    o.imu.model.accel_noise_density = 0.0;
    o.imu.model.gyro_bias_random_walk = 0.0;
    o.imu.model.accel_bias_random_walk = 0.0;
  }
  return sim::SimulateCamera(o);
}

// Initialised from the true states of frames 0 and `second` (a test may), frames in between at
// the truth, the rest through AddFrame.
inline VioRun RunVio(const sim::CameraSimulation& s, SlidingWindowOptions options, bool nees,
                     int point_stride = 1, int second = 3) {
  if (!options.inertial) options.inertial = InertialOptions();
  options.inertial->T_b_c = s.rig.T_b_c;
  options.inertial->gravity_w = s.imu_options.gravity_w;
  VioRun run;
  std::vector<FrameInput> in(s.frame_times.size());
  for (std::size_t i = 0; i < in.size(); ++i) in[i].time = s.frame_times[i];
  for (const auto& p : s.points)
    if (p.point_id % point_stride == 0) in[p.frame].points.push_back(p);
  for (const auto& l : s.segments) in[l.frame].segments.push_back(l);
  SlidingWindowEstimator estimator(s.rig.K, options);
  estimator.AddImu(s.imu);
  const InitializationResult init =
      estimator.InitializeInertial(in[0], TrueState(s, 0), in[second], TrueState(s, second), 10);
  run.initialized = init.ok;
  if (!init.ok) return run;
  for (int i = 0; i <= second; ++i) run.est.push_back(s.T_w_b_gt[i]);
  run.keyframe_of.assign(second + 1, -1);
  double chi2 = 0.0, nees_sum = 0.0;
  std::deque<int> keyframe_frames = {0, second};
  for (std::size_t i = second + 1; i < in.size(); ++i) {
    const WindowFrameResult r = estimator.AddFrame(in[i]);
    run.keyframe_of.push_back(r.keyframe ? static_cast<int>(i) : keyframe_frames.back());
    run.est.push_back(r.state.T_w_b);
    run.keyframes += r.keyframe;
    run.marginalized += r.marginalized_keyframes;
    run.failed_marginalizations += r.marginalization_failed;
    run.imu_only += r.imu_only;
    chi2 += r.imu_chi2;
    if (r.keyframe) keyframe_frames.push_back(static_cast<int>(i));
    if (r.marginalized_keyframes) keyframe_frames.pop_front();
    if (nees && r.keyframe) {
      // Relative to the oldest keyframe's position and yaw (held: the gauge; its roll and pitch
      // are observable and free in the covariance): the estimate moved and turned about the
      // vertical so that its oldest keyframe has the true position and yaw, the error in the
      // PoseManifold tangent of the newest pose.
      const auto cov = estimator.NewestPoseCovariance();
      if (cov) {
        const SE3d& old_gt = s.T_w_b_gt[keyframe_frames.front()];
        const SE3d old_est = estimator.KeyframeStates().front().T_w_b;
        const Eigen::Matrix3d dR = old_gt.RotationMatrix() * old_est.RotationMatrix().transpose();
        const Eigen::Matrix3d R_yaw =
            Eigen::AngleAxisd(std::atan2(dR(1, 0), dR(0, 0)), Eigen::Vector3d::UnitZ())
                .toRotationMatrix();
        const SE3d align(Eigen::Quaterniond(R_yaw),
                         old_gt.translation() - R_yaw * old_est.translation());
        const Vector6d e = (align * r.state.T_w_b).Minus(s.T_w_b_gt[i]);
        nees_sum += e.dot(cov->ldlt().solve(e));
        run.relative[static_cast<int>(i)] = {align * r.state.T_w_b, *cov, keyframe_frames.front()};
        ++run.nees_count;
      }
    }
  }
  run.mean_imu_chi2 = run.keyframes ? chi2 / run.keyframes : 0.0;
  for (std::size_t i = 0; i < run.est.size(); ++i) {
    run.gt.push_back(s.T_w_b_gt[i]);
    run.max_error_m =
        std::max(run.max_error_m, (run.est[i].translation() - s.T_w_b_gt[i].translation()).norm());
  }
  if (run.nees_count) run.mean_nees = nees_sum / run.nees_count;
  return run;
}

}  // namespace window
}  // namespace plucker
