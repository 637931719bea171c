#include "plucker/geometry/orthonormal_line.h"

#include <cmath>

namespace plucker {

void OrthonormalLine::ToParameters(double* p) const {
  p[0] = U.x();
  p[1] = U.y();
  p[2] = U.z();
  p[3] = U.w();
  p[4] = W(0);
  p[5] = W(1);
}

OrthonormalLine OrthonormalLine::FromParameters(const double* p) {
  OrthonormalLine line;
  line.U = Eigen::Quaterniond(p[3], p[0], p[1], p[2]).normalized();
  line.W = Eigen::Vector2d(p[4], p[5]).normalized();
  return line;
}

OrthonormalLine OrthonormalLine::Plus(const Eigen::Vector4d& delta) const {
  OrthonormalLine out;
  out.U = (U * ExpSO3<double>(delta.head<3>())).normalized();
  const double c = std::cos(delta(3)), s = std::sin(delta(3));
  // W R(dphi), first column: the angle of (w1, w2) grows by dphi.
  out.W = Eigen::Vector2d(W(0) * c - W(1) * s, W(0) * s + W(1) * c);
  return out;
}

Eigen::Vector4d OrthonormalLine::Minus(const OrthonormalLine& base) const {
  Eigen::Vector4d delta;
  delta.head<3>() = LogUnitQuaternion<double>(base.U.conjugate() * U);
  // Angle from W_base to W: atan2(W_base x W, W_base . W).
  delta(3) = std::atan2(base.W(0) * W(1) - base.W(1) * W(0), base.W.dot(W));
  return delta;
}

std::optional<OrthonormalLine> OrthonormalFromPlucker(const Line6d& L) {
  if (!L.allFinite()) return std::nullopt;
  const double d_norm = L.tail<3>().norm();
  if (!(d_norm > 0.0) || !std::isfinite(d_norm)) return std::nullopt;
  const Eigen::Vector3d u2 = L.tail<3>() / d_norm;
  Eigen::Vector3d n = L.head<3>() / d_norm;  // scale-free: |n| is now the distance to the origin
  if (!n.allFinite()) return std::nullopt;
  const double n_norm_raw = n.norm();
  if (std::abs(n.dot(u2)) > 1e-6 * n_norm_raw) return std::nullopt;
  n -= u2 * u2.dot(n);  // remove the (small) constraint violation
  const double n_norm = n.norm();

  Eigen::Vector3d u1;
  if (n_norm <= 1e-12) {
    // Through the origin: any unit vector orthogonal to u2, chosen deterministically.
    Eigen::Index k;
    u2.cwiseAbs().minCoeff(&k);
    u1 = u2.cross(Eigen::Vector3d::Unit(k)).normalized();
  } else {
    u1 = n / n_norm;
    u1 = (u1 - u2 * u2.dot(u1)).normalized();
  }
  Eigen::Matrix3d U;
  U.col(0) = u1;
  U.col(1) = u2;
  U.col(2) = u1.cross(u2);

  OrthonormalLine out;
  out.U = Eigen::Quaterniond(U).normalized();
  const double scale = std::sqrt(n_norm * n_norm + 1.0);
  out.W = n_norm <= 1e-12 ? Eigen::Vector2d(0.0, 1.0) : Eigen::Vector2d(n_norm, 1.0) / scale;
  return out;
}

Line6d PluckerFromOrthonormal(const OrthonormalLine& line,
                              Eigen::Matrix<double, 6, 4>* d_L_d_delta) {
  const Eigen::Matrix3d U = line.U.normalized().toRotationMatrix();
  const Eigen::Vector2d W = line.W.normalized();
  const Eigen::Vector3d u1 = U.col(0), u2 = U.col(1), u3 = U.col(2);
  const double w1 = W(0), w2 = W(1);
  if (d_L_d_delta) {
    // du1 = dth3 u2 - dth2 u3, du2 = dth1 u3 - dth3 u1, (dw1, dw2) = (-w2, w1) dphi.
    auto& J = *d_L_d_delta;
    J.block<3, 1>(0, 0).setZero();
    J.block<3, 1>(0, 1) = -w1 * u3;
    J.block<3, 1>(0, 2) = w1 * u2;
    J.block<3, 1>(0, 3) = -w2 * u1;
    J.block<3, 1>(3, 0) = w2 * u3;
    J.block<3, 1>(3, 1).setZero();
    J.block<3, 1>(3, 2) = -w2 * u1;
    J.block<3, 1>(3, 3) = w1 * u2;
  }
  Line6d L;
  L.head<3>() = w1 * u1;
  L.tail<3>() = w2 * u2;
  return L;
}

}  // namespace plucker
