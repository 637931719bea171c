#include "plucker/geometry/point_projection.h"

namespace plucker {

std::optional<Eigen::Vector2d> ProjectCameraPoint(const PinholeIntrinsics& K,
                                                  const Eigen::Vector3d& p_c,
                                                  Eigen::Matrix<double, 2, 3>* d_uv_d_pc,
                                                  double min_depth) {
  if (!K.IsValid() || !p_c.allFinite() || !std::isfinite(min_depth)) return std::nullopt;
  if (!(p_c.z() > min_depth)) return std::nullopt;
  const double inv_z = 1.0 / p_c.z();
  const double x = p_c.x() * inv_z, y = p_c.y() * inv_z;
  if (d_uv_d_pc) {
    // d(x/z)/dp = (1/z) [1, 0, -x/z]; likewise for y.
    *d_uv_d_pc << K.fx * inv_z, 0.0, -K.fx * x * inv_z, 0.0, K.fy * inv_z, -K.fy * y * inv_z;
  }
  return Eigen::Vector2d(K.fx * x + K.cx, K.fy * y + K.cy);
}

std::optional<Eigen::Vector2d> ProjectPoint(const PinholeIntrinsics& K, const SE3d& T_w_c,
                                            const Eigen::Vector3d& p_w,
                                            Eigen::Matrix<double, 2, 6>* d_uv_d_Twc,
                                            Eigen::Matrix<double, 2, 3>* d_uv_d_pw,
                                            double min_depth) {
  if (!T_w_c.rotation().coeffs().allFinite() || !T_w_c.translation().allFinite() ||
      !p_w.allFinite()) {
    return std::nullopt;
  }
  const Eigen::Matrix3d R = T_w_c.RotationMatrix();
  const Eigen::Vector3d p_c = R.transpose() * (p_w - T_w_c.translation());
  Eigen::Matrix<double, 2, 3> d_uv_d_pc;
  const bool need_j = d_uv_d_Twc != nullptr || d_uv_d_pw != nullptr;
  std::optional<Eigen::Vector2d> uv =
      ProjectCameraPoint(K, p_c, need_j ? &d_uv_d_pc : nullptr, min_depth);
  if (!uv) return std::nullopt;
  if (d_uv_d_Twc) {
    // p_c(dtheta, dt) = Exp(-dtheta) R^T (p_w - t - dt) ~ p_c + [p_c]x dtheta - R^T dt.
    d_uv_d_Twc->leftCols<3>() = d_uv_d_pc * Hat<double>(p_c);
    d_uv_d_Twc->rightCols<3>() = -d_uv_d_pc * R.transpose();
  }
  if (d_uv_d_pw) *d_uv_d_pw = d_uv_d_pc * R.transpose();
  return uv;
}

}  // namespace plucker
