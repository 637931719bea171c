#include "plucker/geometry/line_projection.h"

namespace plucker {

Eigen::Matrix3d LineIntrinsics(const PinholeIntrinsics& K) {
  Eigen::Matrix3d K_line;
  K_line << K.fy, 0.0, 0.0,  //
      0.0, K.fx, 0.0,        //
      -K.fy * K.cx, -K.fx * K.cy, K.fx * K.fy;
  return K_line;
}

Eigen::Vector3d ProjectLinePixels(const PinholeIntrinsics& K, const Line6d& L_c,
                                  Eigen::Matrix<double, 3, 6>* d_l_d_Lc) {
  const Eigen::Matrix3d K_line = LineIntrinsics(K);
  if (d_l_d_Lc) {
    d_l_d_Lc->leftCols<3>() = K_line;
    d_l_d_Lc->rightCols<3>().setZero();
  }
  return K_line * L_c.head<3>();
}

std::optional<Eigen::Vector2d> EndpointLineResidual(const Eigen::Vector3d& l_px,
                                                    const Eigen::Vector2d& s_px,
                                                    const Eigen::Vector2d& e_px,
                                                    Eigen::Matrix<double, 2, 3>* d_r_d_l) {
  if (!l_px.allFinite() || !s_px.allFinite() || !e_px.allFinite()) return std::nullopt;
  Eigen::Vector2d r;
  if (!EndpointLineResidualT<double>(l_px, s_px, e_px, &r)) return std::nullopt;
  if (!r.allFinite()) return std::nullopt;
  if (d_r_d_l) {
    const double rho_sq = l_px.head<2>().squaredNorm();
    const double rho = std::sqrt(rho_sq);
    const Eigen::RowVector3d grad_rho(l_px(0), l_px(1), 0.0);  // rho * d rho / d l
    const Eigen::RowVector3d s(s_px(0), s_px(1), 1.0), e(e_px(0), e_px(1), 1.0);
    // r_i = x_i^T l / rho: x_i^T / rho - r_i [l1, l2, 0] / rho^2.
    d_r_d_l->row(0) = s / rho - r(0) * grad_rho / rho_sq;
    d_r_d_l->row(1) = e / rho - r(1) * grad_rho / rho_sq;
  }
  return r;
}

}  // namespace plucker
