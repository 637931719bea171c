// The marginalization of the visual-inertial window (the poses-only prior) on simulated rooms:
// against the joint Schur complement, and against the prior on the landmarks.
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

#include "plucker/window/visual_inertial_test_utils.h"

namespace plucker {
namespace window {
namespace {

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

}  // namespace
}  // namespace window
}  // namespace plucker
