// Point + line bundle adjustment over camera poses, 3D points and 3D lines, assembled from the
// analytic factors (or their autodiff twins, for comparison):
//   points: factors/point_reprojection_factor.h, parameters T_w_c (pose block) and p_w;
//   lines:  factors/line_reprojection_factor.h, parameters T_w_c and the orthonormal line block.
// Gauge: the first `num_fixed_poses` poses are held constant (two fix the monocular scale too).
// Observations that cannot be evaluated at the initial state (point behind the camera, line that
// projects to a point, zero-length segment) are left out and counted, never passed to the solver.
// No I/O: results and statistics are returned to the caller.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/plucker_line.h"
#include "plucker/geometry/se3.h"

namespace plucker {
namespace ba {

struct PointObservation {
  int camera = 0;
  int point = 0;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  // undistorted pixels
};

struct LineObservation {
  int camera = 0;
  int line = 0;
  Eigen::Vector2d s_px = Eigen::Vector2d::Zero();  // undistorted segment endpoints, pixels
  Eigen::Vector2d e_px = Eigen::Vector2d::Zero();
};

// The problem's state (refined in place) and its measurements.
struct BundleAdjustmentData {
  PinholeIntrinsics K;
  std::vector<SE3d> T_w_c;
  std::vector<Eigen::Vector3d> points_w;
  std::vector<Line6d> lines_w;  // Plücker [n; d]; normalised to |d| = 1 on output
  std::vector<PointObservation> point_observations;
  std::vector<LineObservation> line_observations;
};

struct BundleAdjustmentOptions {
  bool use_autodiff = false;    // the autodiff twins instead of the analytic factors
  double point_sigma_px = 1.0;  // measurement standard deviations (square-root information 1/sigma)
  double line_sigma_px = 1.0;
  double huber_threshold = 0.0;  // robust loss scale in units of sigma; 0 = plain least squares
  int num_fixed_poses = 2;
  bool refine_poses = true;
  bool refine_points = true;
  bool refine_lines = true;
  int max_iterations = 100;
  int num_threads = 1;
  double function_tolerance = 1e-12;
  double gradient_tolerance = 1e-12;
  double parameter_tolerance = 1e-12;
};

struct BundleAdjustmentResult {
  bool success = false;       // the solver returned a usable solution
  std::string message;        // Ceres' termination message, or why it did not run
  double initial_cost = 0.0;  // 0.5 * sum of squared weighted residuals
  double final_cost = 0.0;
  int iterations = 0;
  double solve_seconds = 0.0;  // Ceres' total time
  int num_point_residuals = 0;
  int num_line_residuals = 0;
  int skipped_point_observations = 0;  // invalid at the initial state or out of range
  int skipped_line_observations = 0;
  int skipped_lines = 0;  // degenerate Plücker coordinates (not refined)
};

// Refines `data` in place. Throws std::invalid_argument for invalid intrinsics or options.
BundleAdjustmentResult SolveBundleAdjustment(const BundleAdjustmentOptions& options,
                                             BundleAdjustmentData* data);

}  // namespace ba
}  // namespace plucker
