#include "plucker/factors/line_manifold.h"

#include <cmath>

#include "plucker/geometry/orthonormal_line.h"

namespace plucker {

bool IsUsableLineBlock(const double* x) {
  for (int i = 0; i < 6; ++i)
    if (!std::isfinite(x[i])) return false;
  const double q_sq = x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + x[3] * x[3];
  const double w_sq = x[4] * x[4] + x[5] * x[5];
  return q_sq > 0.0 && w_sq > 0.0 && std::isfinite(q_sq) && std::isfinite(w_sq);
}

Eigen::Matrix<double, 6, 4> LinePlusJacobian(const double* x) {
  const OrthonormalLine line = OrthonormalLine::FromParameters(x);
  Eigen::Matrix<double, 6, 4> J = Eigen::Matrix<double, 6, 4>::Zero();
  J.block<4, 3>(0, 0) = QuaternionRightPlusJacobian(line.U);
  J(4, 3) = -line.W(1);
  J(5, 3) = line.W(0);
  return J;
}

Eigen::Matrix<double, 4, 6> LineMinusJacobian(const double* x) {
  const OrthonormalLine line = OrthonormalLine::FromParameters(x);
  Eigen::Matrix<double, 4, 6> J = Eigen::Matrix<double, 4, 6>::Zero();
  J.block<3, 4>(0, 0) = QuaternionRightMinusJacobian(line.U);
  // d atan2(b x y, b . y)/dy at y = b (|b| = 1) = (-b2, b1).
  J(3, 4) = -line.W(1);
  J(3, 5) = line.W(0);
  return J;
}

bool LineManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  if (!IsUsableLineBlock(x)) return false;
  for (int i = 0; i < 4; ++i)
    if (!std::isfinite(delta[i])) return false;
  OrthonormalLine::FromParameters(x)
      .Plus(Eigen::Map<const Eigen::Vector4d>(delta))
      .ToParameters(x_plus_delta);
  return true;
}

bool LineManifold::PlusJacobian(const double* x, double* jacobian) const {
  if (!IsUsableLineBlock(x)) return false;
  Eigen::Map<Eigen::Matrix<double, 6, 4, Eigen::RowMajor>> J(jacobian);
  J = LinePlusJacobian(x);
  return true;
}

bool LineManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  if (!IsUsableLineBlock(x) || !IsUsableLineBlock(y)) return false;
  Eigen::Map<Eigen::Vector4d> out(y_minus_x);
  out = OrthonormalLine::FromParameters(y).Minus(OrthonormalLine::FromParameters(x));
  return true;
}

bool LineManifold::MinusJacobian(const double* x, double* jacobian) const {
  if (!IsUsableLineBlock(x)) return false;
  Eigen::Map<Eigen::Matrix<double, 4, 6, Eigen::RowMajor>> J(jacobian);
  J = LineMinusJacobian(x);
  return true;
}

}  // namespace plucker
