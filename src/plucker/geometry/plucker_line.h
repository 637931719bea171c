// Plücker lines L = [n; d] (moment first, n = p x d), docs/conventions.md.
#pragma once

#include <Eigen/Core>

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

}  // namespace plucker
