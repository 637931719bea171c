// Private to the window layer (not installed): how the oldest keyframe k0 leaves the window.
//
// Two strategies behind one small abstract interface, chosen once in the constructor from
// SlidingWindowOptions::prior_blocks (an interface rather than a function table because each
// strategy also decides the linear solver its prior calls for, and a class keeps the pair
// together with the reason):
//   LandmarkPrior (kLandmarks, landmark_prior_marginalization.cc): k0's observations, its priors
//     and the previous prior are linearised (FEJ) and the Schur complement removes k0 and the
//     landmarks no remaining keyframe observes; the prior lives on the landmarks k0 saw. k0's
//     observations of the lines that stay are kept with k0's pose (retained line-observer poses).
//   PosesOnlyPrior (kPoses, poses_only_marginalization.cc): the landmarks of k0 whose track has
//     ended are eliminated one by one into small priors on their observers' poses, then k0's
//     blocks from those; the prior lives on poses (and, inertial, velocities and biases) only.
// Both end with Impl::InstallPrior and Impl::DropOldestKeyframe (window_state.cc).
#pragma once

#include <ceres/types.h>

#include <memory>

#include "plucker/window/sliding_window_estimator.h"

namespace plucker {
namespace window {
namespace internal {

class MarginalizationStrategy {
 public:
  virtual ~MarginalizationStrategy() = default;
  // Moves the oldest keyframe of `window` into its prior and drops it (with the landmarks that
  // leave), filling the marginalization statistics of `result`.
  virtual void MarginalizeOldest(SlidingWindowEstimator::Impl& window,
                                 WindowFrameResult* result) const = 0;
  // The linear solver of the window solve with this strategy's prior.
  virtual ceres::LinearSolverType WindowLinearSolver() const = 0;
};

std::unique_ptr<MarginalizationStrategy> MakeLandmarkPrior();
std::unique_ptr<MarginalizationStrategy> MakePosesOnlyPrior();

}  // namespace internal
}  // namespace window
}  // namespace plucker
