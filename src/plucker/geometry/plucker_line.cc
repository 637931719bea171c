#include "plucker/geometry/plucker_line.h"

#include <cmath>

namespace plucker {

Eigen::Matrix<double, 6, 6> LineTransformMatrix(const SE3d& T_a_b) {
  const Eigen::Matrix3d R = T_a_b.RotationMatrix();
  Eigen::Matrix<double, 6, 6> H;
  H.block<3, 3>(0, 0) = R;
  H.block<3, 3>(0, 3) = Hat<double>(T_a_b.translation()) * R;
  H.block<3, 3>(3, 0).setZero();
  H.block<3, 3>(3, 3) = R;
  return H;
}

Line6d TransformLine(const SE3d& T_a_b, const Line6d& L_b, Matrix6d* d_La_d_Tab,
                     Matrix6d* d_La_d_Lb, Matrix6d* d_La_d_Tba) {
  const Line6d L_a = TransformLine<double>(T_a_b, L_b);
  if (d_La_d_Lb) *d_La_d_Lb = LineTransformMatrix(T_a_b);
  if (!d_La_d_Tab && !d_La_d_Tba) return L_a;
  const Eigen::Matrix3d R = T_a_b.RotationMatrix();
  const Eigen::Matrix3d R_hat_d = R * Hat<double>(L_b.tail<3>());
  if (d_La_d_Tab) {
    // R Exp(dth) v ~ R v - R [v]x dth; t + dt adds dt x d_a = -[d_a]x dt to n_a.
    d_La_d_Tab->block<3, 3>(0, 0) =
        -R * Hat<double>(L_b.head<3>()) - Hat<double>(T_a_b.translation()) * R_hat_d;
    d_La_d_Tab->block<3, 3>(0, 3) = -Hat<double>(L_a.tail<3>());
    d_La_d_Tab->block<3, 3>(3, 0) = -R_hat_d;
    d_La_d_Tab->block<3, 3>(3, 3).setZero();
  }
  if (d_La_d_Tba) {
    // T_b_a = (R^T, t_b_a) held: (R^T Exp(dth))^T = Exp(-dth) R, so every frame-a vector v_a
    // becomes v_a + [v_a]x dth; n_a = R (n_b - t_b_a x d_b) is linear in t_b_a with R [d_b]x.
    d_La_d_Tba->block<3, 3>(0, 0) = Hat<double>(L_a.head<3>());
    d_La_d_Tba->block<3, 3>(0, 3) = R_hat_d;
    d_La_d_Tba->block<3, 3>(3, 0) = Hat<double>(L_a.tail<3>());
    d_La_d_Tba->block<3, 3>(3, 3).setZero();
  }
  return L_a;
}

bool IsValidLine(const Line6d& L, double tol) {
  if (!L.allFinite()) return false;
  const double n_norm = L.head<3>().norm(), d_norm = L.tail<3>().norm();
  if (!(d_norm > 0.0)) return false;
  return std::abs(L.head<3>().dot(L.tail<3>())) <= tol * n_norm * d_norm;
}

namespace {
// |d| if L is finite with a non-zero direction (and the scaled result stays finite).
std::optional<double> DirectionNorm(const Line6d& L) {
  if (!L.allFinite()) return std::nullopt;
  const double d_norm = L.tail<3>().norm();
  if (!(d_norm > 0.0) || !std::isfinite(d_norm)) return std::nullopt;
  return d_norm;
}
}  // namespace

std::optional<Line6d> NormalizeLineDirection(const Line6d& L) {
  const auto d_norm = DirectionNorm(L);
  if (!d_norm) return std::nullopt;
  const Line6d out = L / *d_norm;
  if (!out.allFinite()) return std::nullopt;
  return out;
}

std::optional<Line6d> NormalizeLine(const Line6d& L) {
  if (!DirectionNorm(L)) return std::nullopt;
  const double norm = L.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) return std::nullopt;
  return Line6d(L / norm);
}

std::optional<Eigen::Vector3d> ClosestPointToOrigin(const Line6d& L) {
  const auto Ln = NormalizeLineDirection(L);
  if (!Ln) return std::nullopt;
  // d x (p x d) = p |d|^2 - d (d . p): the component of p orthogonal to d.
  return Eigen::Vector3d(Ln->tail<3>().cross(Ln->head<3>()));
}

std::optional<Eigen::Vector3d> ClosestPointOnLine(const Line6d& L, const Eigen::Vector3d& x) {
  const auto Ln = NormalizeLineDirection(L);
  if (!Ln || !x.allFinite()) return std::nullopt;
  const Eigen::Vector3d u = Ln->tail<3>();
  const Eigen::Vector3d p0 = u.cross(Ln->head<3>());
  return Eigen::Vector3d(p0 + u * u.dot(x - p0));
}

std::optional<double> PointLineDistance(const Line6d& L, const Eigen::Vector3d& x) {
  const auto Ln = NormalizeLineDirection(L);
  if (!Ln || !x.allFinite()) return std::nullopt;
  // The moment about x: (p - x) x u = n - x x u, its norm is the distance.
  return (Ln->head<3>() - x.cross(Ln->tail<3>())).norm();
}

std::optional<double> LineLineDistance(const Line6d& L1, const Line6d& L2) {
  const auto A = NormalizeLineDirection(L1);
  const auto B = NormalizeLineDirection(L2);
  if (!A || !B) return std::nullopt;
  const Eigen::Vector3d cross = A->tail<3>().cross(B->tail<3>());
  const double sine = cross.norm();
  if (sine > kParallelSine) {
    // Reciprocal product over |d1 x d2|.
    return std::abs(A->tail<3>().dot(B->head<3>()) + B->tail<3>().dot(A->head<3>())) / sine;
  }
  const Eigen::Vector3d p2 = B->tail<3>().cross(B->head<3>());
  return PointLineDistance(*A, p2);
}

}  // namespace plucker
