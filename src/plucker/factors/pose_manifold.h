// The pose manifold: a 7-value block [qx, qy, qz, qw, tx, ty, tz] (geometry/se3.h) with the
// 6-dimensional tangent (dtheta, dt):
//   Plus(x, delta)  = (q * Exp(dtheta), t + dt)
//   Minus(y, x)     = (Log(q_x^-1 q_y), t_y - t_x)         (exact inverse of Plus)
//   PlusJacobian    = d Plus(x, delta)/d delta at 0         (7x6, true, not [I; 0])
//   MinusJacobian   = d Minus(y, x)/d y at y = x            (6x7, a left inverse of PlusJacobian)
#pragma once

#include <ceres/manifold.h>

namespace plucker {

class PoseManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 7; }
  int TangentSize() const override { return 6; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

// A pose whose position and yaw are held: the 2-dimensional tangent is the rotation about the
// world x and y axes (R <- Exp([a, b, 0]) R, i.e. dtheta = R^T [a, b, 0] in the PoseManifold
// tangent). The gauge of a visual-inertial problem (position and yaw) fixed on one pose, its roll
// and pitch (observable through gravity) left free; e.g. the covariance of another pose relative
// to it. Minus(y, x) is the inverse of Plus for y = Plus(x, delta) (the projection of the
// PoseManifold difference onto the tangent otherwise).
class RollPitchPoseManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 7; }
  int TangentSize() const override { return 2; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;

 private:
  PoseManifold pose_;
};

}  // namespace plucker
