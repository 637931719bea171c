// Plücker lines L = [n; d] (moment first, n = p x d), docs/conventions.md, docs/math/lines.md.
//
// A Plücker line is homogeneous (any non-zero scale is the same line) and satisfies n . d = 0.
// The value functions are templates so that the autodiff twins run them with ceres::Jet; the
// analytic Jacobians are double-only (optional output pointers). Pose Jacobians are w.r.t. the
// tangent (dtheta, dt) with R <- R Exp(dtheta), t <- t + dt (geometry/se3.h).
#pragma once

#include <Eigen/Core>
#include <optional>

#include "plucker/geometry/se3.h"

namespace plucker {

template <typename T>
using Line6 = Eigen::Matrix<T, 6, 1>;
using Line6d = Line6<double>;

// Line through p1 and p2: d = p2 - p1, n = p1 x p2 (not normalised).
template <typename T>
Line6<T> LineFromPoints(const Eigen::Matrix<T, 3, 1>& p1, const Eigen::Matrix<T, 3, 1>& p2) {
  Line6<T> L;
  L.template head<3>() = p1.cross(p2);
  L.template tail<3>() = p2 - p1;
  return L;
}

// Intersection of planes pi_i = (m_i, e_i), m_i . x + e_i = 0: d = m2 x m1, n = e2 m1 - e1 m2.
template <typename T>
Line6<T> LineFromPlanes(const Eigen::Matrix<T, 4, 1>& pi1, const Eigen::Matrix<T, 4, 1>& pi2) {
  Line6<T> L;
  L.template head<3>() = pi2(3) * pi1.template head<3>() - pi1(3) * pi2.template head<3>();
  L.template tail<3>() = pi2.template head<3>().cross(pi1.template head<3>());
  return L;
}

// ---------------------------------------------------------------------------------------------
// Rigid transforms of lines.

// H(T_a_b) = [[R, [t]x R], [0, R]]: L_a = H L_b.
Eigen::Matrix<double, 6, 6> LineTransformMatrix(const SE3d& T_a_b);

// L_a = H(T_a_b) L_b, named by frames as poses are (geometry/se3.h): world to camera is
// L_c = TransformLine(T_c_w, L_w), body to camera L_c = TransformLine(T_c_b, L_b).
// Value only, templated for Jets:
//   n_a = R n_b + t x (R d_b),   d_a = R d_b.
template <typename T>
Line6<T> TransformLine(const SE3<T>& T_a_b, const Line6<T>& L_b) {
  const Matrix3<T> R = T_a_b.RotationMatrix();
  const Vector3<T> d_a = R * L_b.template tail<3>();
  Line6<T> L_a;
  L_a.template head<3>() = R * L_b.template head<3>() + T_a_b.translation().cross(d_a);
  L_a.template tail<3>() = d_a;
  return L_a;
}

// Same with Jacobians (this double overload is preferred over the template for doubles):
// d_La_d_Tab w.r.t. the (dtheta, dt) tangent of T_a_b,
//   [[-R[n_b]x - [t]x R [d_b]x, -[d_a]x], [-R [d_b]x, 0]],
// d_La_d_Lb = H(T_a_b), and d_La_d_Tba w.r.t. the tangent of T_b_a = T_a_b^-1, for a solver that
// holds T_b_a (the camera pose T_w_c in L_c = TransformLine(T_c_w, L_w)):
//   [[ [n_a]x, R [d_b]x ], [ [d_a]x, 0 ]]   (= d_La_d_Tab * d_Tab_d_Tba, se3.h Inverse).
Line6d TransformLine(const SE3d& T_a_b, const Line6d& L_b, Matrix6d* d_La_d_Tab = nullptr,
                     Matrix6d* d_La_d_Lb = nullptr, Matrix6d* d_La_d_Tba = nullptr);

// ---------------------------------------------------------------------------------------------
// Validity and normalisation. Every function below returns std::nullopt / false for non-finite
// input or a zero direction; none of them returns NaN.

// Default relative tolerance of the Plücker constraint |n . d| <= tol |n| |d|.
constexpr double kPluckerConstraintTolerance = 1e-9;

// True if L is finite, |d| > 0 and |n . d| <= tol |n| |d|.
bool IsValidLine(const Line6d& L, double tol = kPluckerConstraintTolerance);

// Scaled so that |d| = 1 (then |n| is the distance of the line from the origin).
std::optional<Line6d> NormalizeLineDirection(const Line6d& L);
// Scaled so that |L| = |[n; d]| = 1, with the sign kept.
std::optional<Line6d> NormalizeLine(const Line6d& L);

// ---------------------------------------------------------------------------------------------
// Metric queries (L need not be normalised; |d| > 0 required).

// The point of the line closest to the origin: p0 = (d x n) / |d|^2.
std::optional<Eigen::Vector3d> ClosestPointToOrigin(const Line6d& L);
// The point of the line closest to x: p0 + d (d . (x - p0)) / |d|^2.
std::optional<Eigen::Vector3d> ClosestPointOnLine(const Line6d& L, const Eigen::Vector3d& x);
// Distance of x from the line: |x x d - n| / |d|.
std::optional<double> PointLineDistance(const Line6d& L, const Eigen::Vector3d& x);
// Distance between two lines. Skew (|d1 x d2| > kParallelSine |d1||d2|):
// |d1 . n2 + d2 . n1| / |d1 x d2|; parallel: distance of a point of L2 from L1.
constexpr double kParallelSine = 1e-10;
std::optional<double> LineLineDistance(const Line6d& L1, const Line6d& L2);

}  // namespace plucker
