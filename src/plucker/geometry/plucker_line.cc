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

Line6d TransformLine(const SE3d& T_a_b, const Line6d& L_b, Eigen::Matrix<double, 6, 6>* d_La_d_pose,
                     Eigen::Matrix<double, 6, 6>* d_La_d_Lb) {
  const Line6d L_a = TransformLine<double>(T_a_b, L_b);
  if (d_La_d_pose) {
    // R Exp(dth) v ~ R v - R [v]x dth; t + dt adds dt x d_a = -[d_a]x dt to n_a.
    const Eigen::Matrix3d R = T_a_b.RotationMatrix();
    const Eigen::Matrix3d R_hat_d = R * Hat<double>(L_b.tail<3>());
    d_La_d_pose->block<3, 3>(0, 0) =
        -R * Hat<double>(L_b.head<3>()) - Hat<double>(T_a_b.translation()) * R_hat_d;
    d_La_d_pose->block<3, 3>(0, 3) = -Hat<double>(L_a.tail<3>());
    d_La_d_pose->block<3, 3>(3, 0) = -R_hat_d;
    d_La_d_pose->block<3, 3>(3, 3).setZero();
  }
  if (d_La_d_Lb) *d_La_d_Lb = LineTransformMatrix(T_a_b);
  return L_a;
}

Line6d LineWorldToCamera(const SE3d& T_w_c, const Line6d& L_w,
                         Eigen::Matrix<double, 6, 6>* d_Lc_d_Twc,
                         Eigen::Matrix<double, 6, 6>* d_Lc_d_Lw) {
  const Line6d L_c = LineWorldToCamera<double>(T_w_c, L_w);
  if (d_Lc_d_Twc) {
    // (R Exp(dth))^T = Exp(-dth) R^T: v_c -> v_c - dth x v_c = v_c + [v_c]x dth.
    // n_c = R^T (n_w + [d_w]x t): t + dt adds R^T [d_w]x dt.
    const Eigen::Matrix3d Rt = T_w_c.RotationMatrix().transpose();
    d_Lc_d_Twc->block<3, 3>(0, 0) = Hat<double>(L_c.head<3>());
    d_Lc_d_Twc->block<3, 3>(0, 3) = Rt * Hat<double>(L_w.tail<3>());
    d_Lc_d_Twc->block<3, 3>(3, 0) = Hat<double>(L_c.tail<3>());
    d_Lc_d_Twc->block<3, 3>(3, 3).setZero();
  }
  if (d_Lc_d_Lw) *d_Lc_d_Lw = LineTransformMatrix(T_w_c.Inverse());
  return L_c;
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
