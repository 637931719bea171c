#include "plucker/ba/bundle_adjustment.h"

#include <ceres/ceres.h>

#include <memory>
#include <optional>
#include <stdexcept>

#include "plucker/factors/line_manifold.h"
#include "plucker/factors/line_reprojection_factor.h"
#include "plucker/factors/point_reprojection_factor.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/geometry/orthonormal_line.h"

namespace plucker {
namespace ba {

namespace {

// Evaluates a residual block once at the current state; false when it cannot be evaluated.
bool EvaluatesAt(const ceres::CostFunction& cost, const std::vector<double*>& blocks) {
  double residuals[2];
  return cost.Evaluate(blocks.data(), residuals, nullptr) && std::isfinite(residuals[0]) &&
         std::isfinite(residuals[1]);
}

void ValidateOptions(const BundleAdjustmentOptions& o) {
  if (!(o.point_sigma_px > 0) || !(o.line_sigma_px > 0)) {
    throw std::invalid_argument("bundle adjustment: sigmas must be positive");
  }
  if (!(o.huber_threshold >= 0)) {
    throw std::invalid_argument("bundle adjustment: huber_threshold must be >= 0");
  }
  if (o.num_fixed_poses < 0 || o.max_iterations < 1 || o.num_threads < 1) {
    throw std::invalid_argument("bundle adjustment: invalid iteration, thread or gauge setting");
  }
}

}  // namespace

BundleAdjustmentResult SolveBundleAdjustment(const BundleAdjustmentOptions& options,
                                             BundleAdjustmentData* data) {
  ValidateOptions(options);
  if (!data->K.IsValid()) throw std::invalid_argument("bundle adjustment: invalid intrinsics");
  BundleAdjustmentResult result;

  // Parameter blocks.
  std::vector<std::array<double, 7>> poses(data->T_w_c.size());
  for (std::size_t i = 0; i < poses.size(); ++i) data->T_w_c[i].ToParameters(poses[i].data());
  std::vector<std::array<double, 6>> lines(data->lines_w.size());
  std::vector<bool> line_ok(lines.size(), false);
  for (std::size_t j = 0; j < lines.size(); ++j) {
    const std::optional<OrthonormalLine> o = OrthonormalFromPlucker(data->lines_w[j]);
    if (o) {
      o->ToParameters(lines[j].data());
      line_ok[j] = true;
    } else {
      ++result.skipped_lines;
    }
  }

  // Manifolds live on the stack; the problem owns the cost functions and the (shared) loss.
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  PoseManifold pose_manifold;
  LineManifold line_manifold;
  const Eigen::Matrix2d point_sqrt_info = Eigen::Matrix2d::Identity() / options.point_sigma_px;
  const Eigen::Matrix2d line_sqrt_info = Eigen::Matrix2d::Identity() / options.line_sigma_px;
  ceres::LossFunction* loss = nullptr;
  if (options.huber_threshold > 0) {
    // The residuals are already divided by sigma, so the threshold is in units of sigma.
    loss = new ceres::HuberLoss(options.huber_threshold);
  }

  const int num_poses = static_cast<int>(poses.size());
  for (const PointObservation& obs : data->point_observations) {
    if (obs.camera < 0 || obs.camera >= num_poses || obs.point < 0 ||
        obs.point >= static_cast<int>(data->points_w.size())) {
      ++result.skipped_point_observations;
      continue;
    }
    std::unique_ptr<ceres::CostFunction> cost;
    try {
      cost.reset(options.use_autodiff
                     ? PointReprojectionFactor::CreateAutoDiff(data->K, obs.uv, point_sqrt_info)
                     : PointReprojectionFactor::Create(data->K, obs.uv, point_sqrt_info));
    } catch (const std::invalid_argument&) {
      ++result.skipped_point_observations;
      continue;
    }
    const std::vector<double*> blocks = {poses[obs.camera].data(),
                                         data->points_w[obs.point].data()};
    if (!EvaluatesAt(*cost, blocks)) {
      ++result.skipped_point_observations;
      continue;
    }
    problem.AddResidualBlock(cost.release(), loss, blocks);
    ++result.num_point_residuals;
  }
  for (const LineObservation& obs : data->line_observations) {
    if (obs.camera < 0 || obs.camera >= num_poses || obs.line < 0 ||
        obs.line >= static_cast<int>(lines.size()) || !line_ok[obs.line]) {
      ++result.skipped_line_observations;
      continue;
    }
    std::unique_ptr<ceres::CostFunction> cost;
    try {
      cost.reset(
          options.use_autodiff
              ? LineReprojectionFactor::CreateAutoDiff(data->K, obs.s_px, obs.e_px, line_sqrt_info)
              : LineReprojectionFactor::Create(data->K, obs.s_px, obs.e_px, line_sqrt_info));
    } catch (const std::invalid_argument&) {
      ++result.skipped_line_observations;
      continue;
    }
    const std::vector<double*> blocks = {poses[obs.camera].data(), lines[obs.line].data()};
    if (!EvaluatesAt(*cost, blocks)) {
      ++result.skipped_line_observations;
      continue;
    }
    problem.AddResidualBlock(cost.release(), loss, blocks);
    ++result.num_line_residuals;
  }
  if (result.num_point_residuals + result.num_line_residuals == 0) {
    delete loss;  // never handed to the problem
    result.message = "no valid observation";
    return result;
  }

  for (int i = 0; i < num_poses; ++i) {
    if (!problem.HasParameterBlock(poses[i].data())) continue;
    problem.SetManifold(poses[i].data(), &pose_manifold);
    if (i < options.num_fixed_poses || !options.refine_poses) {
      problem.SetParameterBlockConstant(poses[i].data());
    }
  }
  for (auto& p : data->points_w) {
    if (problem.HasParameterBlock(p.data()) && !options.refine_points) {
      problem.SetParameterBlockConstant(p.data());
    }
  }
  for (auto& l : lines) {
    if (!problem.HasParameterBlock(l.data())) continue;
    problem.SetManifold(l.data(), &line_manifold);
    if (!options.refine_lines) problem.SetParameterBlockConstant(l.data());
  }

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_SCHUR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.num_threads = options.num_threads;
  solver_options.function_tolerance = options.function_tolerance;
  solver_options.gradient_tolerance = options.gradient_tolerance;
  solver_options.parameter_tolerance = options.parameter_tolerance;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);

  result.success = summary.IsSolutionUsable();
  result.message = summary.message;
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  result.iterations = static_cast<int>(summary.iterations.size());
  result.solve_seconds = summary.total_time_in_seconds;

  for (int i = 0; i < num_poses; ++i) data->T_w_c[i] = SE3d::FromParameters(poses[i].data());
  for (std::size_t j = 0; j < lines.size(); ++j) {
    if (line_ok[j]) {
      data->lines_w[j] = PluckerFromOrthonormal(OrthonormalLine::FromParameters(lines[j].data()));
      if (const auto n = NormalizeLineDirection(data->lines_w[j])) data->lines_w[j] = *n;
    }
  }
  return result;
}

}  // namespace ba
}  // namespace plucker
