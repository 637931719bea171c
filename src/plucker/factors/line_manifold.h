// The line manifold (orthonormal representation, geometry/orthonormal_line.h): a 6-value block
// [qx, qy, qz, qw, w1, w2] with the 4-dimensional tangent (dtheta1, dtheta2, dtheta3, dphi):
//   Plus(x, delta)  = (U Exp(dtheta), W R(dphi))
//   Minus(y, x)     = (Log(U_x^-1 U_y) on S^3, angle(W_y) - angle(W_x))   (exact inverse of Plus)
//   PlusJacobian    = d Plus(x, delta)/d delta at 0        (6x4, true, storage coordinates)
//   MinusJacobian   = d Minus(y, x)/d y at y = x           (4x6, a left inverse of PlusJacobian)
// Every method returns false for non-finite input (or a zero quaternion / zero W).
#pragma once

#include <ceres/manifold.h>

#include <Eigen/Core>

namespace plucker {

class LineManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 6; }
  int TangentSize() const override { return 4; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

// Finite, with a non-zero quaternion and a non-zero W: the blocks the manifold and the line
// factors accept.
bool IsUsableLineBlock(const double* x);

// The same Jacobians as Eigen matrices (x need not be normalised; it is normalised first).
Eigen::Matrix<double, 6, 4> LinePlusJacobian(const double* x);
Eigen::Matrix<double, 4, 6> LineMinusJacobian(const double* x);

}  // namespace plucker
