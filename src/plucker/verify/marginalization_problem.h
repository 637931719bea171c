// A small visual problem for the marginalization tests and checks: cameras T_w_c on a line
// looking along +z at points and lines 4-8 m ahead, with point and line reprojection factors
// (0.5 px noise). The blocks' storage and the manifolds live in the struct (do not copy it).
#pragma once

#include <ceres/cost_function.h>

#include <memory>
#include <vector>

#include "plucker/factors/line_manifold.h"
#include "plucker/factors/marginalization.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace verify {

struct MarginalizationProblem {
  std::vector<std::vector<double>> poses, points, lines;  // 7, 3 and 6 values
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  std::vector<MarginalizationResidual> residuals;
  std::vector<MarginalizationBlock> blocks;  // poses, then points, then lines
  PoseManifold pose_manifold;
  LineManifold line_manifold;

  MarginalizationProblem() = default;
  MarginalizationProblem(const MarginalizationProblem&) = delete;
  MarginalizationProblem& operator=(const MarginalizationProblem&) = delete;

  // The residuals that touch `block` (what a sliding window marginalizes with it).
  std::vector<MarginalizationResidual> ResidualsOf(const std::vector<double*>& blocks) const;
};

std::unique_ptr<MarginalizationProblem> MakeMarginalizationProblem(Rng& rng, int num_poses,
                                                                   int num_points, int num_lines);

}  // namespace verify
}  // namespace plucker
