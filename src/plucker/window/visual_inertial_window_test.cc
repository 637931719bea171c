// The visual-inertial mode of the sliding window (SlidingWindowOptions::inertial) on simulated
// rooms: noise-free, with MEMS noise, and the NEES of the newest pose.
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
namespace {

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

sim::CameraSimulation Simulate(int frames, bool noise, std::uint64_t seed) {
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
VioRun RunVio(const sim::CameraSimulation& s, SlidingWindowOptions options, bool nees,
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

TEST(VisualInertialWindow, NoiseFreeRecoversThePosesToAMillimetre) {
  const sim::CameraSimulation s = Simulate(60, false, 3);
  SlidingWindowOptions options;
  const VioRun run = RunVio(s, options, false, 2);
  ASSERT_TRUE(run.initialized);
  std::printf(
      "noise-free VIO room: %zu frames, %d keyframes (%d marginalized), max error %.2e m, "
      "mean IMU chi2 %.2e\n",
      run.est.size(), run.keyframes, run.marginalized, run.max_error_m, run.mean_imu_chi2);
  EXPECT_EQ(run.est.size(), s.frame_times.size());
  EXPECT_GT(run.marginalized, 10);
  EXPECT_EQ(run.failed_marginalizations, 0);
  EXPECT_LT(run.max_error_m, 1e-3);
}

// MEMS-like IMU noise (the simulator's default model, also the estimator's) and 1 px pixel noise:
// the position + yaw aligned ATE over 20 s, and the NEES of the newest pose (6 expected).
TEST(VisualInertialWindow, MemsNoiseGivesASmallPositionYawAteAndASaneNees) {
  const sim::CameraSimulation s = Simulate(200, true, 5);
  SlidingWindowOptions options;
  const VioRun run = RunVio(s, options, true, 3);
  ASSERT_TRUE(run.initialized);
  const eval::AteResult ate =
      eval::ComputeAte(run.gt, run.est, {eval::AlignmentMode::kPositionYaw});
  std::printf(
      "MEMS VIO room: %zu frames, %d keyframes, ATE (posyaw) %.4f m, max error %.4f m, "
      "mean IMU chi2 %.3g (15 dof), mean NEES %.2f over %d keyframes (6 expected), "
      "%d IMU-only frames\n",
      run.est.size(), run.keyframes, ate.translation_m.rmse, run.max_error_m, run.mean_imu_chi2,
      run.mean_nees, run.nees_count, run.imu_only);
  EXPECT_EQ(run.failed_marginalizations, 0);
  EXPECT_LT(ate.translation_m.rmse, 0.05);
  EXPECT_GT(run.nees_count, 20);
  EXPECT_LT(run.mean_nees, 12.0);  // 6.42 (13.0 when the covariance held roll and pitch)
  EXPECT_GT(run.mean_nees, 3.0);
}

// The per-frame tracking with the IMU prediction as a prior (InertialOptions::
// tracking_velocity_sigma) against vision-only tracking (0), MEMS room, 4 s: the frames between
// keyframes, whose pose is the tracking's, relative to the keyframe they were predicted from
// (the error of a frame minus the error of that keyframe) are several times closer to the truth.
TEST(VisualInertialWindow, TrackingWithTheImuPredictionIsCloserThanVisionOnly) {
  const sim::CameraSimulation s = Simulate(40, true, 5);
  double local_rms[2] = {0.0, 0.0};
  int frames[2] = {0, 0};
  for (int with_imu = 0; with_imu < 2; ++with_imu) {
    SlidingWindowOptions options;
    options.inertial = InertialOptions();
    if (!with_imu) options.inertial->tracking_velocity_sigma = 0.0;
    const VioRun run = RunVio(s, options, false, 3);
    ASSERT_TRUE(run.initialized);
    ASSERT_EQ(run.est.size(), s.frame_times.size());
    double sum = 0.0;
    for (std::size_t i = 1; i < run.est.size(); ++i) {
      if (run.keyframe_of[i] < 0 || run.keyframe_of[i] == static_cast<int>(i)) continue;
      const int k = run.keyframe_of[i];
      const Eigen::Vector3d e = run.est[i].translation() - run.gt[i].translation();
      const Eigen::Vector3d e_k = run.est[k].translation() - run.gt[k].translation();
      sum += (e - e_k).squaredNorm();
      ++frames[with_imu];
    }
    local_rms[with_imu] = std::sqrt(sum / std::max(frames[with_imu], 1));
    const eval::AteResult ate =
        eval::ComputeAte(run.gt, run.est, {eval::AlignmentMode::kPositionYaw});
    std::printf(
        "%s tracking: %d frames between keyframes, error relative to their keyframe "
        "%.2f mm rms, ATE (posyaw) %.4f m\n",
        with_imu ? "IMU-prior" : "vision-only", frames[with_imu], 1e3 * local_rms[with_imu],
        ate.translation_m.rmse);
  }
  EXPECT_GE(frames[0], 10);
  EXPECT_GE(frames[1], 10);
  EXPECT_LT(local_rms[1], 0.5 * local_rms[0]);
  // A negative or non-finite velocity sigma is refused.
  SlidingWindowOptions bad;
  bad.inertial = InertialOptions();
  bad.inertial->tracking_velocity_sigma = -0.01;
  EXPECT_THROW(SlidingWindowEstimator(s.rig.K, bad), std::invalid_argument);
  bad.inertial->tracking_velocity_sigma = std::numeric_limits<double>::infinity();
  EXPECT_THROW(SlidingWindowEstimator(s.rig.K, bad), std::invalid_argument);
}

// r = (x - x0) / sigma on a vector block.
template <int kN>
struct VectorPriorCost {
  Eigen::Matrix<double, kN, 1> x0;
  double inv_sigma;
  template <typename T>
  bool operator()(const T* x, T* r) const {
    for (int i = 0; i < kN; ++i) r[i] = (x[i] - T(x0(i))) * T(inv_sigma);
    return true;
  }
};
// The poses-only prior of the inertial mode eliminates in two stages: each leaving landmark with
// all its observations (a prior on its observers' poses), then the oldest keyframe's pose,
// velocity and bias from those priors, its state priors and its IMU factor. On a small problem
// (3 keyframes of the simulated room, the points all three see, MEMS noise, Huber loss) the
// result equals the one-shot Schur complement of the same residuals (MarginalizationPrior,
// itself checked against a dense Schur complement), blocks pose_1, v_1, b_1, pose_2.
TEST(VisualInertialWindow, PosesOnlyPriorEqualsTheJointSchurComplement) {
  const sim::CameraSimulation s = Simulate(10, true, 4);
  const int kf[3] = {0, 3, 6};
  const sensor::ImuModel model = s.imu_options.model;
  PoseManifold pose_manifold;
  ceres::HuberLoss huber(1.5);
  double pose[3][7], v[3][3], bias[3][6];
  for (int k = 0; k < 3; ++k) {
    const sensor::BodyState st = TrueState(s, kf[k]);
    st.T_w_b.ToParameters(pose[k]);
    for (int i = 0; i < 3; ++i) {
      v[k][i] = st.v_w(i) + 0.01 * (i + 1);  // off the truth: non-zero residuals
      bias[k][i] = st.bias.gyro(i);
      bias[k][3 + i] = st.bias.accel(i) + 0.02;
    }
  }
  // Points seen by all three keyframes, at their scene positions moved by 2 cm.
  std::map<int, std::vector<std::pair<int, Eigen::Vector2d>>> obs;
  for (const auto& p : s.points)
    for (int k = 0; k < 3; ++k)
      if (p.frame == kf[k]) obs[p.point_id].push_back({k, p.uv});
  std::map<int, std::array<double, 3>> lm;
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  std::vector<MarginalizationResidual> joint;
  std::vector<std::vector<MarginalizationResidual>> per_landmark;
  for (const auto& [id, list] : obs) {
    if (list.size() != 3 || lm.size() >= 12) continue;
    const Eigen::Vector3d p = s.scene.points_w[id] + Eigen::Vector3d(0.02, -0.01, 0.015);
    lm[id] = {p.x(), p.y(), p.z()};
  }
  ASSERT_GE(lm.size(), 8u);
  for (auto& [id, x] : lm) {
    per_landmark.emplace_back();
    for (const auto& [k, uv] : obs[id]) {
      costs.emplace_back(new HeldExtrinsicFactor<3>(
          PointReprojectionFactorVI::Create(s.rig.K, uv, Eigen::Matrix2d::Identity()),
          s.rig.T_b_c));
      const MarginalizationResidual r{costs.back().get(), &huber, {pose[k], x.data()}};
      joint.push_back(r);
      per_landmark.back().push_back(r);
    }
  }
  // k0's IMU factor and state priors.
  std::vector<MarginalizationResidual> inertial;
  const ImuPreintegration pre = PreintegrateSamples(
      s.imu, s.frame_times[kf[0]], s.frame_times[kf[1]], TrueState(s, kf[0]).bias, model);
  costs.emplace_back(ImuFactor::Create(pre, s.imu_options.gravity_w));
  inertial.push_back(
      {costs.back().get(), nullptr, {pose[0], v[0], bias[0], pose[1], v[1], bias[1]}});
  costs.emplace_back(new ceres::AutoDiffCostFunction<VectorPriorCost<3>, 3, 3>(
      new VectorPriorCost<3>{Eigen::Vector3d(v[0]) + Eigen::Vector3d::Constant(0.01), 10.0}));
  inertial.push_back({costs.back().get(), nullptr, {v[0]}});
  costs.emplace_back(new ceres::AutoDiffCostFunction<VectorPriorCost<6>, 6, 6>(
      new VectorPriorCost<6>{Eigen::Matrix<double, 6, 1>(bias[0]), 100.0}));
  inertial.push_back({costs.back().get(), nullptr, {bias[0]}});
  joint.insert(joint.end(), inertial.begin(), inertial.end());

  auto state_blocks = [&](std::vector<MarginalizationBlock>* b) {
    for (int k = 0; k < 3; ++k) {
      b->push_back({pose[k], 7, &pose_manifold});
      if (k < 2) b->push_back({v[k], 3, nullptr});
      if (k < 2) b->push_back({bias[k], 6, nullptr});
    }
  };
  // One shot.
  std::vector<MarginalizationBlock> all;
  state_blocks(&all);
  std::vector<double*> remove = {pose[0], v[0], bias[0]};
  for (auto& [id, x] : lm) {
    all.push_back({x.data(), 3, nullptr});
    remove.push_back(x.data());
  }
  const MarginalizationPrior one = MarginalizationPrior::Build(all, joint, remove);
  // Two stages, as the window does.
  std::vector<MarginalizationPrior> stage1;
  std::vector<std::unique_ptr<ceres::CostFunction>> stage1_costs;
  std::vector<MarginalizationResidual> stage2 = inertial;
  int i = 0;
  for (auto& [id, x] : lm) {
    std::vector<MarginalizationBlock> b = {{x.data(), 3, nullptr}};
    for (int k = 0; k < 3; ++k) b.push_back({pose[k], 7, &pose_manifold});
    stage1.push_back(MarginalizationPrior::Build(b, per_landmark[i++], {x.data()}));
    stage1_costs.emplace_back(stage1.back().CreateCostFunction());
    MarginalizationResidual r{stage1_costs.back().get(), nullptr, {}};
    for (const auto& kb : stage1.back().KeptBlocks()) r.blocks.push_back(kb.values);
    stage2.push_back(r);
  }
  std::vector<MarginalizationBlock> states;
  state_blocks(&states);
  const MarginalizationPrior two =
      MarginalizationPrior::Build(states, stage2, {pose[0], v[0], bias[0]});

  // Compare H* and g* block by block (the kept blocks' order may differ).
  auto offsets = [](const MarginalizationPrior& p) {
    std::map<const double*, std::pair<int, int>> o;
    int at = 0;
    for (const auto& b : p.KeptBlocks()) {
      const int n = b.manifold ? b.manifold->TangentSize() : b.ambient_size;
      o[b.values] = {at, n};
      at += n;
    }
    return o;
  };
  const auto o1 = offsets(one), o2 = offsets(two);
  ASSERT_EQ(o1.size(), 4u);
  ASSERT_EQ(o2.size(), 4u);
  const Eigen::MatrixXd H1 = one.Information(), H2 = two.Information();
  const Eigen::VectorXd g1 = one.Gradient(), g2 = two.Gradient();
  double worst_H = 0.0, worst_g = 0.0;
  int compared = 0;
  for (const auto& [a, ra] : o1) {
    ASSERT_TRUE(o2.count(a));
    const auto sa = o2.at(a);
    worst_g = std::max(
        worst_g,
        (g1.segment(ra.first, ra.second) - g2.segment(sa.first, sa.second)).cwiseAbs().maxCoeff());
    for (const auto& [b, rb] : o1) {
      const auto sb = o2.at(b);
      const Eigen::MatrixXd d = H1.block(ra.first, rb.first, ra.second, rb.second) -
                                H2.block(sa.first, sb.first, sa.second, sb.second);
      worst_H = std::max(worst_H, d.cwiseAbs().maxCoeff());
      compared += static_cast<int>(d.size());
    }
  }
  std::printf(
      "poses-only inertial prior vs one-shot Schur: %zu landmarks, kept dimension %d, rank %d, "
      "max |dH| %.2e (|H| %.2e), max |dg| %.2e (|g| %.2e), %d entries\n",
      lm.size(), static_cast<int>(H1.rows()), one.Statistics().prior_rank, worst_H,
      H1.cwiseAbs().maxCoeff(), worst_g, g1.cwiseAbs().maxCoeff(), compared);
  EXPECT_EQ(compared, 21 * 21);                // pose_1, v_1, b_1, pose_2
  EXPECT_GT(one.Statistics().prior_rank, 15);  // the velocity and biases of keyframe 1 included
  EXPECT_LT(worst_H, 1e-9 * H1.cwiseAbs().maxCoeff());
  EXPECT_LT(worst_g, 1e-9 * std::max(1.0, g1.cwiseAbs().maxCoeff()));
}

// The poses-only prior in the inertial mode against the prior on the landmarks (both FEJ) on the
// MEMS room (4 s, a window of 5): the newest keyframe poses (relative to the oldest keyframe's
// position and yaw, where both runs have the same oldest keyframe) differ by about the
// landmark-prior run's own standard deviation; ATE and NEES of both reported.
TEST(VisualInertialWindow, PosesOnlyPriorMatchesTheLandmarkPriorWithinItsCovariance) {
  const sim::CameraSimulation s = Simulate(40, true, 5);
  SlidingWindowOptions full, poses;
  full.window_size = poses.window_size = 5;  // marginalizations early, solves short
  poses.prior_blocks = SlidingWindowOptions::PriorBlocks::kPoses;
  poses.retire_marginalized_tracks = false;  // as plucker vio: the ids are scene ids
  const VioRun a = RunVio(s, full, true, 3), b = RunVio(s, poses, true, 3);
  ASSERT_TRUE(a.initialized && b.initialized);
  const eval::AteResult ate_a = eval::ComputeAte(a.gt, a.est, {eval::AlignmentMode::kPositionYaw});
  const eval::AteResult ate_b = eval::ComputeAte(b.gt, b.est, {eval::AlignmentMode::kPositionYaw});
  double d2 = 0.0;
  int compared = 0;
  for (const auto& [frame, ra] : a.relative) {
    const auto it = b.relative.find(frame);
    if (it == b.relative.end() || it->second.oldest != ra.oldest) continue;
    const Vector6d d = it->second.T_w_b.Minus(ra.T_w_b);
    d2 += d.dot(ra.cov.ldlt().solve(d));
    ++compared;
  }
  std::printf(
      "MEMS VIO room, landmark prior vs poses-only prior: ATE (posyaw) %.4f / %.4f m, mean NEES "
      "%.2f / %.2f (6 expected), %d / %d keyframes, difference of the newest poses whitened by "
      "the landmark prior's covariance %.2f on average over %d keyframes\n",
      ate_a.translation_m.rmse, ate_b.translation_m.rmse, a.mean_nees, b.mean_nees, a.keyframes,
      b.keyframes, compared ? d2 / compared : 0.0, compared);
  EXPECT_EQ(b.failed_marginalizations, 0);
  EXPECT_GT(b.marginalized, 10);
  EXPECT_GT(compared, 10);
  // Two consistent estimates whose errors have this covariance differ by d with E[d^T S^-1 d] at
  // most 12 (12 when independent); measured 8.4: the two priors give estimates about 1.2
  // standard deviations apart.
  EXPECT_LT(d2 / compared, 12.0);
  EXPECT_LT(b.mean_nees, 12.0);
  EXPECT_LT(ate_b.translation_m.rmse, 0.05);
}

// Bad IMU input: samples that go back are refused; a frame the samples do not cover yet is
// refused (std::invalid_argument) without changing the window, which goes on once they arrive.
TEST(VisualInertialWindow, UncoveredFramesAreRefusedAndTheWindowGoesOn) {
  const sim::CameraSimulation s = Simulate(30, true, 2);
  SlidingWindowOptions options;
  options.inertial = InertialOptions();
  options.inertial->T_b_c = s.rig.T_b_c;
  std::vector<FrameInput> in(s.frame_times.size());
  for (std::size_t i = 0; i < in.size(); ++i) in[i].time = s.frame_times[i];
  for (const auto& p : s.points) in[p.frame].points.push_back(p);
  SlidingWindowEstimator estimator(s.rig.K, options);
  const double t_cut = s.frame_times[10] + 0.01;
  std::vector<sensor::ImuSample> early, late;
  for (const auto& m : s.imu) (m.t <= t_cut ? early : late).push_back(m);
  estimator.AddImu(early);
  EXPECT_THROW(estimator.AddImu({early.front()}), std::invalid_argument);
  ASSERT_TRUE(estimator.InitializeInertial(in[0], TrueState(s, 0), in[3], TrueState(s, 3)).ok);
  for (int i = 4; i <= 10; ++i) ASSERT_NO_THROW(estimator.AddFrame(in[i]));
  const std::size_t keyframes = estimator.KeyframeStates().size();
  EXPECT_THROW(estimator.AddFrame(in[11]), std::invalid_argument);
  EXPECT_EQ(estimator.KeyframeStates().size(), keyframes);
  estimator.AddImu(late);
  int finite = 0;
  for (std::size_t i = 11; i < in.size(); ++i) {
    const WindowFrameResult r = estimator.AddFrame(in[i]);
    finite += r.state.T_w_b.translation().allFinite() && r.state.v_w.allFinite();
    EXPECT_LT((r.state.T_w_b.translation() - s.T_w_b_gt[i].translation()).norm(), 0.2) << i;
  }
  EXPECT_EQ(finite, static_cast<int>(in.size()) - 11);
  EXPECT_THROW(SlidingWindowEstimator(s.rig.K, SlidingWindowOptions()).AddImu(late),
               std::logic_error);
}

TEST(VisualInertialWindow, StartsWithManyKeyframesAndTriangulatesTheLandmarksOfEach) {
  const sim::CameraSimulation s = Simulate(30, false, 3);
  SlidingWindowOptions options;
  options.inertial = InertialOptions();
  options.inertial->T_b_c = s.rig.T_b_c;
  options.inertial->gravity_w = s.imu_options.gravity_w;
  std::vector<FrameInput> in(s.frame_times.size());
  for (std::size_t i = 0; i < in.size(); ++i) in[i].time = s.frame_times[i];
  for (const auto& p : s.points) in[p.frame].points.push_back(p);
  const std::vector<int> kf = {0, 5, 10, 15, 20};
  std::vector<FrameInput> frames;
  std::vector<sensor::BodyState> states;
  for (int f : kf) {
    frames.push_back(in[f]);
    states.push_back(TrueState(s, f));
  }
  // Perturbed starts (as an alignment gives them): the window's solve brings them back.
  for (std::size_t k = 1; k < states.size(); ++k) {
    states[k].T_w_b = SE3d(states[k].T_w_b.rotation(),
                           states[k].T_w_b.translation() + Eigen::Vector3d(0.03, -0.02, 0.01));
  }
  SlidingWindowEstimator many(s.rig.K, options), two(s.rig.K, options);
  many.AddImu(s.imu);
  two.AddImu(s.imu);
  const InitializationResult r = many.InitializeInertial(frames, states, 10);
  ASSERT_TRUE(r.ok);
  ASSERT_TRUE(two.InitializeInertial(in[0], TrueState(s, 0), in[20], TrueState(s, 20), 10).ok);
  const std::vector<sensor::BodyState> solved = many.KeyframeStates();
  ASSERT_EQ(solved.size(), kf.size());
  double max_error = 0.0;
  for (std::size_t k = 0; k < kf.size(); ++k) {
    max_error = std::max(max_error,
                         (solved[k].T_w_b.translation() - s.T_w_b_gt[kf[k]].translation()).norm());
  }
  std::printf("5-keyframe start: %d points (2 keyframes: %zu), max position error %.2e m\n",
              r.points, two.Points().size(), max_error);
  EXPECT_LT(max_error, 2e-3);  // noise-free: the 3.7 cm perturbations are removed
  EXPECT_GT(r.points, static_cast<int>(two.Points().size()));  // tracks not seen by the newest
  for (int i = 21; i < 30; ++i) {
    const WindowFrameResult fr = many.AddFrame(in[i]);
    EXPECT_LT((fr.state.T_w_b.translation() - s.T_w_b_gt[i].translation()).norm(), 5e-3) << i;
  }
  EXPECT_THROW(many.InitializeInertial(frames, {states.front()}), std::invalid_argument);
  options.window_size = 4;
  SlidingWindowEstimator small(s.rig.K, options);
  small.AddImu(s.imu);
  EXPECT_THROW(small.InitializeInertial(frames, states), std::invalid_argument);
}

// The caller's "no image motion" flag: believed for a standing body (its pose held by the
// zero-motion factors against an accelerometer offset), ignored for a moving one (forward motion
// can look still in the image).
TEST(VisualInertialWindow, TheStationaryFlagHoldsAStandingBodyAndIsIgnoredWhenItMoves) {
  const sim::CameraSimulation s = Simulate(16, true, 5);  // short: sanitizer budget
  SlidingWindowOptions options;
  options.inertial = InertialOptions();
  options.inertial->T_b_c = s.rig.T_b_c;
  options.inertial->gravity_w = s.imu_options.gravity_w;
  {  // Standing: frame 0's view repeated, the IMU reading gravity plus a 0.05 m/s^2 offset.
    sensor::BodyState still;
    still.T_w_b = s.T_w_b_gt[0];
    std::vector<sensor::ImuSample> imu;
    for (int k = 0; k <= 500; ++k) {
      sensor::ImuSample m;
      m.t = 0.005 * k;
      m.accel = still.T_w_b.RotationMatrix().transpose() * -s.imu_options.gravity_w +
                Eigen::Vector3d(0.05, 0.0, 0.0);
      imu.push_back(m);
    }
    std::vector<FrameInput> in(21);
    for (std::size_t i = 0; i < in.size(); ++i) {
      in[i].time = 0.1 * static_cast<double>(i);
      in[i].stationary = true;
      for (const auto& p : s.points)
        if (p.frame == 0) in[i].points.push_back(p);
    }
    SlidingWindowEstimator estimator(s.rig.K, options);
    estimator.AddImu(imu);
    ASSERT_TRUE(estimator.InitializeInertial(in[0], still, in[1], still, 0).ok);
    int held = 0;
    double drift = 0.0;
    for (std::size_t i = 2; i < in.size(); ++i) {
      const WindowFrameResult r = estimator.AddFrame(in[i]);
      held += r.stationary;
      drift = std::max(drift, (r.state.T_w_b.translation() - still.T_w_b.translation()).norm());
    }
    std::printf("standing body: %d of %zu frames held, drift %.2e m (the offset alone: %.3f m)\n",
                held, in.size() - 2, drift, 0.5 * 0.05 * 2.0 * 2.0);
    EXPECT_EQ(held, static_cast<int>(in.size()) - 2);
    EXPECT_LT(drift, 2e-3);
  }
  {  // Moving, every frame flagged: the flags are ignored, the poses tracked.
    std::vector<FrameInput> in(s.frame_times.size());
    for (std::size_t i = 0; i < in.size(); ++i) {
      in[i].time = s.frame_times[i];
      in[i].stationary = true;
    }
    for (const auto& p : s.points) in[p.frame].points.push_back(p);
    SlidingWindowEstimator estimator(s.rig.K, options);
    estimator.AddImu(s.imu);
    ASSERT_GT(s.v_w_gt[3].norm(), 5.0 * options.inertial->stationary_max_speed);
    ASSERT_TRUE(estimator.InitializeInertial(in[0], TrueState(s, 0), in[3], TrueState(s, 3)).ok);
    int held = 0, checked = 0;
    for (std::size_t i = 4; i < in.size(); ++i) {
      const WindowFrameResult r = estimator.AddFrame(in[i]);
      held += r.stationary;
      EXPECT_LT((r.state.T_w_b.translation() - s.T_w_b_gt[i].translation()).norm(), 0.1) << i;
      ++checked;
    }
    EXPECT_EQ(held, 0);
    EXPECT_EQ(checked, static_cast<int>(in.size()) - 4);
  }
}

}  // namespace
}  // namespace window
}  // namespace plucker
