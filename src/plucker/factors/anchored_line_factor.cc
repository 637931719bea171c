#include "plucker/factors/anchored_line_factor.h"

#include <ceres/autodiff_cost_function.h>

#include <cmath>
#include <stdexcept>

#include "plucker/factors/line_reprojection_factor.h"

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

}  // namespace

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

}  // namespace plucker
