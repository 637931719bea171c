#include "plucker/factors/anchored_line_factor.h"

#include <ceres/autodiff_cost_function.h>

#include <cmath>
#include <stdexcept>

#include "plucker/factors/line_reprojection_factor.h"
#include "plucker/factors/pose_block.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/geometry/so3.h"

namespace plucker {
namespace {

void CheckAnchor(const LineAnchor& anchor) {
  if (!anchor.c_w.allFinite() || !std::isfinite(anchor.scale) || !(anchor.scale > 0.0)) {
    throw std::invalid_argument("AnchoredLineFactor: the anchor must be finite with scale > 0");
  }
}

// The autodiff twin: the inner residual on the pose moved into the anchor frame.
struct AnchoredLineResidual {
  LineReprojectionResidual inner;
  LineAnchor anchor;
  template <typename T>
  bool operator()(const T* T_w_c, const T* line, T* residual) const {
    T pose_a[7];
    for (int i = 0; i < 4; ++i) pose_a[i] = T_w_c[i];
    for (int i = 0; i < 3; ++i) pose_a[4 + i] = (T_w_c[4 + i] - T(anchor.c_w(i))) / T(anchor.scale);
    return inner(pose_a, line, residual);
  }
};

// The autodiff twin of the VI factor: the anchored residual on T_w_b T_b_c.
struct AnchoredLineResidualVI {
  AnchoredLineResidual camera;
  template <typename T>
  bool operator()(const T* T_w_b, const T* T_b_c, const T* line, T* residual) const {
    T T_w_c[7];
    (SE3<T>::FromParameters(T_w_b) * SE3<T>::FromParameters(T_b_c)).ToParameters(T_w_c);
    return camera(T_w_c, line, residual);
  }
};

}  // namespace

SE3d CameraFromBody(const SE3d& T_w_b, const SE3d& T_b_c, Matrix6d* J_wb, Matrix6d* J_bc) {
  const Eigen::Matrix3d R_wb = T_w_b.RotationMatrix();
  if (J_wb) {
    J_wb->setZero();
    J_wb->topLeftCorner<3, 3>() = T_b_c.RotationMatrix().transpose();
    J_wb->bottomLeftCorner<3, 3>() = -R_wb * Hat<double>(T_b_c.translation());
    J_wb->bottomRightCorner<3, 3>().setIdentity();
  }
  if (J_bc) {
    J_bc->setZero();
    J_bc->topLeftCorner<3, 3>().setIdentity();
    J_bc->bottomRightCorner<3, 3>() = R_wb;
  }
  return T_w_b * T_b_c;
}

LineAnchor MakeLineAnchor(const Line6d& L_w, const Eigen::Vector3d& camera_centre_w) {
  LineAnchor anchor;
  anchor.c_w = camera_centre_w;
  const std::optional<double> distance = PointLineDistance(L_w, camera_centre_w);
  anchor.scale = (distance && std::isfinite(*distance) && *distance > 1e-9) ? *distance : 1.0;
  return anchor;
}

Line6d AnchoredFromWorld(const Line6d& L_w, const LineAnchor& anchor) {
  const Eigen::Vector3d d = L_w.tail<3>();
  Line6d L_a;
  L_a.head<3>() = (L_w.head<3>() - anchor.c_w.cross(d)) / anchor.scale;
  L_a.tail<3>() = d;
  return L_a;
}

Line6d WorldFromAnchored(const Line6d& L_a, const LineAnchor& anchor) {
  const Eigen::Vector3d d = L_a.tail<3>();
  Line6d L_w;
  L_w.head<3>() = anchor.scale * L_a.head<3>() + anchor.c_w.cross(d);
  L_w.tail<3>() = d;
  return L_w;
}

ceres::CostFunction* AnchoredLineFactor::Create(const PinholeIntrinsics& K,
                                                const Eigen::Vector2d& s_px,
                                                const Eigen::Vector2d& e_px,
                                                const Eigen::Matrix2d& sqrt_information,
                                                const LineAnchor& anchor) {
  CheckAnchor(anchor);
  return new AnchoredLineFactor(LineReprojectionFactor::Create(K, s_px, e_px, sqrt_information),
                                anchor);
}

ceres::CostFunction* AnchoredLineFactor::CreateAutoDiff(const PinholeIntrinsics& K,
                                                        const Eigen::Vector2d& s_px,
                                                        const Eigen::Vector2d& e_px,
                                                        const Eigen::Matrix2d& sqrt_information,
                                                        const LineAnchor& anchor) {
  CheckAnchor(anchor);
  return new ceres::AutoDiffCostFunction<AnchoredLineResidual, 2, 7, 6>(new AnchoredLineResidual{
      LineReprojectionResidual(MakeLineSegmentMeasurement(K, s_px, e_px, sqrt_information)),
      anchor});
}

bool AnchoredLineFactor::Evaluate(double const* const* parameters, double* residuals,
                                  double** jacobians) const {
  const double* T_w_c = parameters[0];
  double pose_a[7];
  for (int i = 0; i < 4; ++i) pose_a[i] = T_w_c[i];
  for (int i = 0; i < 3; ++i) pose_a[4 + i] = (T_w_c[4 + i] - anchor_.c_w(i)) / anchor_.scale;
  const double* inner_parameters[2] = {pose_a, parameters[1]};
  if (!inner_->Evaluate(inner_parameters, residuals, jacobians)) return false;
  if (jacobians != nullptr && jacobians[0] != nullptr) {
    for (int r = 0; r < 2; ++r) {
      for (int c = 4; c < 7; ++c) jacobians[0][7 * r + c] /= anchor_.scale;
    }
  }
  return true;
}

ceres::CostFunction* AnchoredLineFactorVI::Create(const PinholeIntrinsics& K,
                                                  const Eigen::Vector2d& s_px,
                                                  const Eigen::Vector2d& e_px,
                                                  const Eigen::Matrix2d& sqrt_information,
                                                  const LineAnchor& anchor) {
  return new AnchoredLineFactorVI(
      AnchoredLineFactor::Create(K, s_px, e_px, sqrt_information, anchor));
}

ceres::CostFunction* AnchoredLineFactorVI::CreateAutoDiff(const PinholeIntrinsics& K,
                                                          const Eigen::Vector2d& s_px,
                                                          const Eigen::Vector2d& e_px,
                                                          const Eigen::Matrix2d& sqrt_information,
                                                          const LineAnchor& anchor) {
  CheckAnchor(anchor);
  return new ceres::AutoDiffCostFunction<AnchoredLineResidualVI, 2, 7, 7, 6>(
      new AnchoredLineResidualVI{
          {LineReprojectionResidual(MakeLineSegmentMeasurement(K, s_px, e_px, sqrt_information)),
           anchor}});
}

bool AnchoredLineFactorVI::Evaluate(double const* const* parameters, double* residuals,
                                    double** jacobians) const {
  Eigen::Quaterniond q_wb, q_bc;
  Eigen::Vector3d t_wb, t_bc;
  if (!pose_block::Read(parameters[0], &q_wb, nullptr, &t_wb) ||
      !pose_block::Read(parameters[1], &q_bc, nullptr, &t_bc)) {
    return false;
  }
  const bool need_pose_j = jacobians && (jacobians[0] || jacobians[1]);
  Matrix6d J_wb, J_bc;
  const SE3d T_w_c = CameraFromBody(SE3d(q_wb, t_wb), SE3d(q_bc, t_bc),
                                    need_pose_j ? &J_wb : nullptr, need_pose_j ? &J_bc : nullptr);
  double pose_c[7];
  T_w_c.ToParameters(pose_c);
  const double* camera_parameters[2] = {pose_c, parameters[2]};
  Eigen::Matrix<double, 2, 7, Eigen::RowMajor> J_c_ambient;
  double* camera_jacobians[2] = {need_pose_j ? J_c_ambient.data() : nullptr,
                                 jacobians ? jacobians[2] : nullptr};
  if (!camera_->Evaluate(camera_parameters, residuals, jacobians ? camera_jacobians : nullptr)) {
    return false;
  }
  if (!need_pose_j) return true;
  // The tangent Jacobian of T_w_c (ambient times PlusJacobian), then the link.
  Eigen::Matrix<double, 7, 6, Eigen::RowMajor> plus;
  PoseManifold().PlusJacobian(pose_c, plus.data());
  const Eigen::Matrix<double, 2, 6> J_c = J_c_ambient * plus;
  if (jacobians[0]) {
    const Eigen::Matrix<double, 2, 6> J = J_c * J_wb;
    pose_block::WriteAmbient<2>(J.leftCols<3>(), J.rightCols<3>(), q_wb, jacobians[0]);
  }
  if (jacobians[1]) {
    const Eigen::Matrix<double, 2, 6> J = J_c * J_bc;
    pose_block::WriteAmbient<2>(J.leftCols<3>(), J.rightCols<3>(), q_bc, jacobians[1]);
  }
  return true;
}

}  // namespace plucker
