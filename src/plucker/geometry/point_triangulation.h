// N-view triangulation of a 3D point from ideal (undistorted) pixel observations: a normalised
// linear (DLT) solution refined by Gauss-Newton on the reprojection error.
// Derivations: docs/math/projection-triangulation.md.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/se3.h"

namespace plucker {

struct PointTriangulationOptions {
  int min_views = 2;              // fewer observations -> kTooFewViews (values < 2 act as 2)
  double min_parallax_deg = 1.0;  // largest angle between any two bearing rays must reach it
  double min_depth = 1e-3;        // the point must be this far in front of every camera (m)
  bool refine = true;             // Gauss-Newton on the reprojection error after the DLT
  int max_iterations = 20;        // Gauss-Newton iterations
  double step_tolerance = 1e-10;  // converged when |dx| <= step_tolerance * (1 + |x|)
  double cost_tolerance = 1e-14;  // ... or the relative cost decrease falls below this
};

enum class PointTriangulationStatus {
  kOk,
  kInvalidInput,  // non-finite pose/pixel, invalid intrinsics, size mismatch
  kTooFewViews,
  kSmallParallax,  // max pairwise ray angle below min_parallax_deg (e.g. all cameras on one ray)
  kDegenerate,     // the linear system has no finite solution (point at infinity)
  kBehindCamera,   // the solution is not in front of every camera
  kNotConverged,   // Gauss-Newton hit max_iterations; `point` holds the last iterate
};
const char* ToString(PointTriangulationStatus status);

struct PointTriangulationResult {
  PointTriangulationStatus status = PointTriangulationStatus::kInvalidInput;
  std::string message;                            // human-readable reason when status != kOk
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();  // valid when ok(); last estimate otherwise
  double max_parallax_rad = 0.0;  // largest angle between two observation rays, taken as
                                  // lines (in [0, pi/2]: opposite rays count as parallel)
  // RMS over the views of the reprojection error norm |uv_i - project(p_w)| (pixels).
  double initial_rms_px = 0.0;  // of the linear solution
  double final_rms_px = 0.0;    // after refinement (== initial when refine is false)
  int iterations = 0;
  bool ok() const { return status == PointTriangulationStatus::kOk; }
};

// T_w_c[i] observes the point at the ideal pixel uv[i] with intrinsics K.
PointTriangulationResult TriangulatePoint(const PinholeIntrinsics& K,
                                          const std::vector<SE3d>& T_w_c,
                                          const std::vector<Eigen::Vector2d>& uv,
                                          const PointTriangulationOptions& options = {});

}  // namespace plucker
