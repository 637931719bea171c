// Orthonormal representation of a Plücker line (4 degrees of freedom), docs/math/lines.md.
//
//   U = [u1 u2 u3] = [n/|n|, d/|d|, (n x d)/|n x d|]  in SO(3), stored as a unit quaternion;
//   W = (w1, w2) = (|n|, |d|) / sqrt(|n|^2 + |d|^2)   a unit 2-vector (the SO(2) matrix
//       [[w1, -w2], [w2, w1]]), w1/w2 = distance of the line from the origin.
//   Back to Plücker (unit scale): L = (w1 u1, w2 u2).
// Parameter storage (6 doubles, line manifold block): [qx, qy, qz, qw, w1, w2].
// Tangent (dtheta1, dtheta2, dtheta3, dphi): U <- U Exp(dtheta), W <- W R(dphi), i.e. the angle
// phi = atan2(w2, w1) grows by dphi. No Euler angles anywhere (no gimbal lock).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>

#include "plucker/geometry/plucker_line.h"

namespace plucker {

struct OrthonormalLine {
  Eigen::Quaterniond U = Eigen::Quaterniond::Identity();
  Eigen::Vector2d W = Eigen::Vector2d(0.0, 1.0);

  static constexpr int kAmbientSize = 6;
  static constexpr int kTangentSize = 4;

  // [qx, qy, qz, qw, w1, w2].
  void ToParameters(double* p) const;
  // From 6 stored values; normalises q and W (they need not be unit).
  static OrthonormalLine FromParameters(const double* p);

  // (U Exp(dtheta), W R(dphi)).
  OrthonormalLine Plus(const Eigen::Vector4d& delta) const;
  // Exact inverse of Plus: (Log(U_base^-1 U) on S^3, angle(W) - angle(W_base) in (-pi, pi]).
  Eigen::Vector4d Minus(const OrthonormalLine& base) const;
};

// Plücker -> orthonormal. Fails (nullopt) for non-finite L, |d| = 0, or a constraint violation
// |n . d| > 1e-6 |n||d|; smaller violations are removed by projecting n orthogonal to d.
// Lines through the origin (|n| <= 1e-12 |d|) get w1 = 0 and a deterministic u1: the normalised
// cross product of u2 with the coordinate axis least aligned with u2.
std::optional<OrthonormalLine> OrthonormalFromPlucker(const Line6d& L);

// Orthonormal -> Plücker L = (w1 u1, w2 u2) from the 6 raw parameters [qx qy qz qw w1 w2];
// normalises q and W inside, so with Jets it yields the exact ambient derivative (autodiff twin).
template <typename T>
Line6<T> PluckerFromOrthonormal(const T* p) {
  using std::sqrt;
  const Eigen::Quaternion<T> q = Eigen::Quaternion<T>(p[3], p[0], p[1], p[2]).normalized();
  const T w_norm = sqrt(p[4] * p[4] + p[5] * p[5]);
  const Matrix3<T> U = q.toRotationMatrix();
  Line6<T> L;
  L.template head<3>() = (p[4] / w_norm) * U.col(0);
  L.template tail<3>() = (p[5] / w_norm) * U.col(1);
  return L;
}

// Orthonormal -> Plücker with the 6x4 Jacobian w.r.t. the tangent (rows n then d; columns
// dtheta1..3, dphi):
//   [[ 0,      -w1 u3,  w1 u2, -w2 u1 ],
//    [ w2 u3,   0,     -w2 u1,  w1 u2 ]]
Line6d PluckerFromOrthonormal(const OrthonormalLine& line,
                              Eigen::Matrix<double, 6, 4>* d_L_d_delta = nullptr);

}  // namespace plucker
