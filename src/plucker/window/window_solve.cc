// The window solve (Ceres, the problem of window_residuals.cc) and the culling after it.
#include <ceres/solver.h>

#include <cmath>

#include "plucker/window/window_internal.h"

namespace plucker {
namespace window {

using internal::ObservationBlock;

void SlidingWindowEstimator::Impl::SolveWindow(WindowFrameResult* result) {
  RepropagateImu();
  UpdateExtrinsicFree();
  PredictImageVelocities();
  ceres::Problem problem(ProblemOptions());
  std::vector<ObservationBlock> observations;
  result->residuals = BuildProblem(&problem, true, &observations);
  ceres::Solver::Options so;
  // Dense for a poses-only prior, sparse for the landmark prior (the strategies say why).
  so.linear_solver_type = marginalization->WindowLinearSolver();
  so.max_num_iterations = opt.max_iterations;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  result->window_iterations = static_cast<int>(summary.iterations.size()) - 1;
  result->initial_cost = summary.initial_cost;
  result->final_cost = summary.final_cost;
  SyncExtrinsic();
  // Cull outliers (the problem's own residual blocks, at the solution) and landmarks left with
  // too few observations.
  result->culled_observations = CullOutliers(problem, observations, result);
  result->culled_observations += PruneRetained(true);
  RemoveWeakLandmarks();
}

// Marks the observations whose residual in `problem` (at the current values) cannot be
// evaluated or exceeds the outlier threshold; returns the number marked.
// `stats` (optional): the line/point split (line_residuals, culled_line_observations and the RMS
// of the kept residuals).
int SlidingWindowEstimator::Impl::CullOutliers(const ceres::Problem& problem,
                                               const std::vector<ObservationBlock>& observations,
                                               WindowFrameResult* stats) const {
  int culled = 0, culled_lines = 0, lines_total = 0;
  double sq[2] = {0.0, 0.0};
  int kept[2] = {0, 0};  // points, lines
  for (const ObservationBlock& o : observations) {
    lines_total += !o.is_point;
    double res[2];
    const bool ok = problem.EvaluateResidualBlock(o.id, false, nullptr, res, nullptr) &&
                    std::isfinite(res[0]) && std::isfinite(res[1]);
    const double norm = ok ? std::hypot(res[0], res[1]) : 0.0;
    if (ok && norm <= opt.outlier_sigmas) {
      sq[o.is_point ? 0 : 1] += norm * norm;
      ++kept[o.is_point ? 0 : 1];
      continue;
    }
    (o.is_point ? o.frame->point_outlier : o.frame->segment_outlier)[o.observation] = 1;
    ++culled;
    culled_lines += !o.is_point;
  }
  if (stats) {
    stats->line_residuals = lines_total;
    stats->culled_line_observations = culled_lines;
    stats->point_rms_sigmas = kept[0] > 0 ? std::sqrt(sq[0] / kept[0]) : 0.0;
    stats->line_rms_sigmas = kept[1] > 0 ? std::sqrt(sq[1] / kept[1]) : 0.0;
  }
  return culled;
}

}  // namespace window
}  // namespace plucker
