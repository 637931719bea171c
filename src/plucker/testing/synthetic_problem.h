// A bundle adjustment problem built from a camera simulation: ground truth, and an initial state
// made by perturbing the true poses (except the gauge poses), points and lines with seeded noise.
// Used by the convergence tests, `plucker demo` and `plucker bench ba`.
#pragma once

#include <cstdint>
#include <vector>

#include "plucker/ba/accuracy.h"
#include "plucker/ba/bundle_adjustment.h"
#include "plucker/sim/camera_observations.h"

namespace plucker {
namespace ba {

struct SyntheticProblemOptions {
  sim::CameraSimulationOptions simulation;
  double rotation_noise_deg = 1.0;     // per-axis sigma of the initial pose rotation error
  double translation_noise_m = 0.1;    // per-axis sigma of the initial pose translation error
  double point_noise_m = 0.1;          // per-axis sigma of the initial point error
  double line_endpoint_noise_m = 0.1;  // per-axis sigma on the segment endpoints of initial lines
  int min_observations = 3;            // structure seen fewer times is left out
  // Structure without enough parallax is unobservable in depth (its back-projected planes or rays
  // nearly coincide) and is left out, as a triangulation front end would: the largest angle
  // between two back-projected plane normals (lines) or two rays (points), true geometry.
  double min_line_parallax_deg = 5.0;
  double min_point_parallax_deg = 2.0;
  int num_fixed_poses = 2;  // not perturbed (the gauge of the solve)
  std::uint64_t seed = 7;
};

struct SyntheticProblem {
  sim::CameraSimulation simulation;
  BundleAdjustmentData initial;  // perturbed state + inlier observations
  std::vector<SE3d> T_w_c_gt;
  std::vector<Eigen::Vector3d> points_gt;  // same indexing as initial.points_w
  std::vector<WorldSegment> segments_gt;   // same indexing as initial.lines_w
};

// Throws std::invalid_argument for invalid options (see sim::SimulateCamera).
SyntheticProblem MakeSyntheticProblem(const SyntheticProblemOptions& options);

// Accuracy of a state against the problem's ground truth (CompareToGroundTruth).
ProblemAccuracy Evaluate(const SyntheticProblem& problem, const BundleAdjustmentData& state,
                         eval::AlignmentMode alignment = eval::AlignmentMode::kNone);

}  // namespace ba
}  // namespace plucker
