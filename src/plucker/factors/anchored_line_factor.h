// A line block conditioned by scene-scale normalisation (docs/vo.md, "Far lines").
//
// In the orthonormal form the distance of a line from the origin is w1/w2 = tan(phi): a line far
// from the world origin sits near phi = pi/2, where a step dphi moves it by (1 + dist^2) dphi, and
// the tangent is badly scaled (the core round measured 109 iterations for lines alone). The window
// therefore stores every line in its own anchor frame: x_a = (x_w - c) / s, with c a point off the
// line (the centre of the first camera that observed it) and s its distance from c, so that the
// anchored line has distance 1 (phi = pi/4) whatever its world position and scale.
//
// The factor (2 | 7, 6), parameters T_w_c and the anchored line block, is the verified
// LineReprojectionFactor evaluated on the pose expressed in the anchor frame,
//   T_a_c = (q_w_c, (t_w_c - c) / s),
// which is exact because the residual is homogeneous in the image line (scaling the scene by 1/s
// scales n_c by 1/s and leaves the endpoint distances unchanged). Chain rule: the pose's
// translation columns of the ambient Jacobian are divided by s; everything else is the inner
// factor's. The autodiff twin (CreateAutoDiff) is checked against it in the test.
//
// AnchoredLineFactorVI (2 | 7, 7, 6), parameters T_w_b (body pose), T_b_c (camera-body extrinsic)
// and the anchored line block, is the same residual on T_w_c = T_w_b T_b_c: one more chain-rule
// link, CameraFromBody below (tested on its own against central differences on the manifold), so
// that J_b = J_c dT_w_c/dT_w_b and J_bc = J_c dT_w_c/dT_b_c in the PoseManifold tangents. A null
// jacobians[1] is honoured (the extrinsic held), as PointReprojectionFactorVI does.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <memory>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/plucker_line.h"
#include "plucker/geometry/se3.h"

namespace plucker {

// The anchor of a line: x_a = (x_w - c_w) / scale. c_w = 0, scale = 1 is the plain world line.
struct LineAnchor {
  Eigen::Vector3d c_w = Eigen::Vector3d::Zero();
  double scale = 1.0;
};

// The anchor for a world line seen from a camera centre: c_w = the centre, scale = the line's
// distance from it (1 if that distance is not positive and finite).
LineAnchor MakeLineAnchor(const Line6d& L_w, const Eigen::Vector3d& camera_centre_w);

// World line <-> anchored line (Plücker, homogeneous: any positive scale of the result is the
// same line).
Line6d AnchoredFromWorld(const Line6d& L_w, const LineAnchor& anchor);
Line6d WorldFromAnchored(const Line6d& L_a, const LineAnchor& anchor);

// T_w_c = T_w_b T_b_c with its Jacobians in the PoseManifold tangents (rotation on the right,
// translation in the world: Plus(x, d) = (q Exp(dtheta), t + dt)):
//   dT_w_c/dT_w_b = [[R_bc^T, 0], [-R_wb [t_bc]x, I]],   dT_w_c/dT_b_c = [[I, 0], [0, R_wb]].
SE3d CameraFromBody(const SE3d& T_w_b, const SE3d& T_b_c, Matrix6d* J_wb = nullptr,
                    Matrix6d* J_bc = nullptr);

class AnchoredLineFactor final : public ceres::SizedCostFunction<2, 7, 6> {
 public:
  // Throws std::invalid_argument like LineReprojectionFactor::Create, and for a non-finite
  // anchor or a scale that is not positive.
  static ceres::CostFunction* Create(const PinholeIntrinsics& K, const Eigen::Vector2d& s_px,
                                     const Eigen::Vector2d& e_px,
                                     const Eigen::Matrix2d& sqrt_information,
                                     const LineAnchor& anchor);
  static ceres::CostFunction* CreateAutoDiff(const PinholeIntrinsics& K,
                                             const Eigen::Vector2d& s_px,
                                             const Eigen::Vector2d& e_px,
                                             const Eigen::Matrix2d& sqrt_information,
                                             const LineAnchor& anchor);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  AnchoredLineFactor(ceres::CostFunction* inner, const LineAnchor& anchor)
      : inner_(inner), anchor_(anchor) {}
  std::unique_ptr<ceres::CostFunction> inner_;
  LineAnchor anchor_;
};

class AnchoredLineFactorVI final : public ceres::SizedCostFunction<2, 7, 7, 6> {
 public:
  // Throws std::invalid_argument as AnchoredLineFactor::Create.
  static ceres::CostFunction* Create(const PinholeIntrinsics& K, const Eigen::Vector2d& s_px,
                                     const Eigen::Vector2d& e_px,
                                     const Eigen::Matrix2d& sqrt_information,
                                     const LineAnchor& anchor);
  static ceres::CostFunction* CreateAutoDiff(const PinholeIntrinsics& K,
                                             const Eigen::Vector2d& s_px,
                                             const Eigen::Vector2d& e_px,
                                             const Eigen::Matrix2d& sqrt_information,
                                             const LineAnchor& anchor);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  explicit AnchoredLineFactorVI(ceres::CostFunction* camera_factor) : camera_(camera_factor) {}
  std::unique_ptr<ceres::CostFunction> camera_;  // the AnchoredLineFactor on T_w_c
};

}  // namespace plucker
