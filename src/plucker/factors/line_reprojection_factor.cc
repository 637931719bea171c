#include "plucker/factors/line_reprojection_factor.h"

#include <cmath>
#include <stdexcept>

#include "plucker/factors/line_manifold.h"

namespace plucker {

namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using RowMajor2x7 = Eigen::Matrix<double, 2, 7, Eigen::RowMajor>;
using RowMajor2x6 = Eigen::Matrix<double, 2, 6, Eigen::RowMajor>;

bool AllFinite(const double* v, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

// A finite pose block with a non-zero quaternion.
bool UsablePose(const double* p) {
  if (!AllFinite(p, 7)) return false;
  const double q_sq = p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + p[3] * p[3];
  return q_sq > 0.0 && std::isfinite(q_sq);
}

bool UsableLine(const double* p) {
  if (!AllFinite(p, 6)) return false;
  const double q_sq = p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + p[3] * p[3];
  const double w_sq = p[4] * p[4] + p[5] * p[5];
  return q_sq > 0.0 && w_sq > 0.0 && std::isfinite(q_sq) && std::isfinite(w_sq);
}

// d Minus(y, x)/d y of the pose manifold at x (6x7), for a normalised quaternion.
Eigen::Matrix<double, 6, 7> PoseMinusJacobian(const SE3d& pose) {
  Eigen::Matrix<double, 6, 7> J = Eigen::Matrix<double, 6, 7>::Zero();
  J.block<3, 4>(0, 0) = QuaternionRightMinusJacobian(pose.rotation());
  J.block<3, 3>(3, 4).setIdentity();
  return J;
}

// The residual of a camera-frame line and, if d_r_d_Lc is given, its 2x6 Jacobian (weighted).
bool ResidualFromCameraLine(const LineSegmentMeasurement& obs, const Line6d& L_c, double* residuals,
                            Eigen::Matrix<double, 2, 6>* d_r_d_Lc) {
  if (LineThroughCameraCentre<double>(L_c)) return false;
  const Eigen::Vector3d l = obs.K_line * L_c.head<3>();
  Eigen::Matrix<double, 2, 3> d_r_d_l;
  const auto r = EndpointLineResidual(l, obs.s_px, obs.e_px, d_r_d_Lc ? &d_r_d_l : nullptr);
  if (!r) return false;
  const Eigen::Vector2d weighted = obs.sqrt_information * *r;
  if (!weighted.allFinite()) return false;
  Eigen::Map<Eigen::Vector2d> r_out(residuals);
  r_out = weighted;
  if (d_r_d_Lc) {
    d_r_d_Lc->leftCols<3>() = obs.sqrt_information * d_r_d_l * obs.K_line;
    d_r_d_Lc->rightCols<3>().setZero();
  }
  return true;
}

}  // namespace

LineSegmentMeasurement MakeLineSegmentMeasurement(const PinholeIntrinsics& K,
                                                  const Eigen::Vector2d& s_px,
                                                  const Eigen::Vector2d& e_px,
                                                  const Eigen::Matrix2d& sqrt_information) {
  if (!K.IsValid()) throw std::invalid_argument("line factor: invalid pinhole intrinsics");
  if (!s_px.allFinite() || !e_px.allFinite()) {
    throw std::invalid_argument("line factor: non-finite segment endpoint");
  }
  if (!((e_px - s_px).norm() >= kMinSegmentLengthPx)) {
    throw std::invalid_argument("line factor: zero-length segment (endpoints coincide)");
  }
  if (!sqrt_information.allFinite()) {
    throw std::invalid_argument("line factor: non-finite square-root information");
  }
  return LineSegmentMeasurement{LineIntrinsics(K), s_px, e_px, sqrt_information};
}

// ---------------------------------------------------------------------------------------------

ceres::CostFunction* LineReprojectionFactor::Create(const PinholeIntrinsics& K,
                                                    const Eigen::Vector2d& s_px,
                                                    const Eigen::Vector2d& e_px,
                                                    const Eigen::Matrix2d& sqrt_information) {
  return new LineReprojectionFactor(MakeLineSegmentMeasurement(K, s_px, e_px, sqrt_information));
}

ceres::CostFunction* LineReprojectionFactor::CreateAutoDiff(
    const PinholeIntrinsics& K, const Eigen::Vector2d& s_px, const Eigen::Vector2d& e_px,
    const Eigen::Matrix2d& sqrt_information) {
  return new ceres::AutoDiffCostFunction<LineReprojectionResidual, 2, 7, 6>(
      new LineReprojectionResidual(MakeLineSegmentMeasurement(K, s_px, e_px, sqrt_information)));
}

bool LineReprojectionFactor::Evaluate(double const* const* parameters, double* residuals,
                                      double** jacobians) const {
  if (!UsablePose(parameters[0]) || !UsableLine(parameters[1])) return false;
  const SE3d T_w_c = SE3d::FromParameters(parameters[0]);
  const OrthonormalLine line = OrthonormalLine::FromParameters(parameters[1]);
  const bool want_pose = jacobians && jacobians[0];
  const bool want_line = jacobians && jacobians[1];

  Eigen::Matrix<double, 6, 4> d_Lw_d_delta;
  const Line6d L_w = PluckerFromOrthonormal(line, want_line ? &d_Lw_d_delta : nullptr);
  Matrix6d d_Lc_d_Twc, d_Lc_d_Lw;
  const Line6d L_c = LineWorldToCamera(T_w_c, L_w, want_pose ? &d_Lc_d_Twc : nullptr,
                                       want_line ? &d_Lc_d_Lw : nullptr);
  Eigen::Matrix<double, 2, 6> d_r_d_Lc;
  if (!ResidualFromCameraLine(obs_, L_c, residuals, jacobians ? &d_r_d_Lc : nullptr)) {
    return false;
  }
  if (want_pose) {
    const Eigen::Matrix<double, 2, 6> J_tangent = d_r_d_Lc * d_Lc_d_Twc;
    Eigen::Map<RowMajor2x7>{jacobians[0]} = J_tangent * PoseMinusJacobian(T_w_c);
  }
  if (want_line) {
    const Eigen::Matrix<double, 2, 4> J_tangent = d_r_d_Lc * d_Lc_d_Lw * d_Lw_d_delta;
    Eigen::Map<RowMajor2x6>{jacobians[1]} = J_tangent * LineMinusJacobian(parameters[1]);
  }
  return true;
}

// ---------------------------------------------------------------------------------------------

ceres::CostFunction* LineReprojectionFactorVI::Create(const PinholeIntrinsics& K,
                                                      const Eigen::Vector2d& s_px,
                                                      const Eigen::Vector2d& e_px,
                                                      const Eigen::Matrix2d& sqrt_information) {
  return new LineReprojectionFactorVI(MakeLineSegmentMeasurement(K, s_px, e_px, sqrt_information));
}

ceres::CostFunction* LineReprojectionFactorVI::CreateAutoDiff(
    const PinholeIntrinsics& K, const Eigen::Vector2d& s_px, const Eigen::Vector2d& e_px,
    const Eigen::Matrix2d& sqrt_information) {
  return new ceres::AutoDiffCostFunction<LineReprojectionResidualVI, 2, 7, 7, 6>(
      new LineReprojectionResidualVI(MakeLineSegmentMeasurement(K, s_px, e_px, sqrt_information)));
}

bool LineReprojectionFactorVI::Evaluate(double const* const* parameters, double* residuals,
                                        double** jacobians) const {
  if (!UsablePose(parameters[0]) || !UsablePose(parameters[1]) || !UsableLine(parameters[2])) {
    return false;
  }
  const SE3d T_w_b = SE3d::FromParameters(parameters[0]);
  const SE3d T_b_c = SE3d::FromParameters(parameters[1]);
  const OrthonormalLine line = OrthonormalLine::FromParameters(parameters[2]);
  const bool want_body = jacobians && jacobians[0];
  const bool want_extrinsic = jacobians && jacobians[1];
  const bool want_line = jacobians && jacobians[2];

  Eigen::Matrix<double, 6, 4> d_Lw_d_delta;
  const Line6d L_w = PluckerFromOrthonormal(line, want_line ? &d_Lw_d_delta : nullptr);
  Matrix6d d_Lb_d_Twb, d_Lb_d_Lw, d_Lc_d_Tbc, d_Lc_d_Lb;
  const Line6d L_b = LineWorldToCamera(T_w_b, L_w, want_body ? &d_Lb_d_Twb : nullptr,
                                       want_line ? &d_Lb_d_Lw : nullptr);
  const Line6d L_c = LineWorldToCamera(T_b_c, L_b, want_extrinsic ? &d_Lc_d_Tbc : nullptr,
                                       (want_body || want_line) ? &d_Lc_d_Lb : nullptr);
  Eigen::Matrix<double, 2, 6> d_r_d_Lc;
  if (!ResidualFromCameraLine(obs_, L_c, residuals, jacobians ? &d_r_d_Lc : nullptr)) {
    return false;
  }
  if (want_body) {
    const Eigen::Matrix<double, 2, 6> J_tangent = d_r_d_Lc * d_Lc_d_Lb * d_Lb_d_Twb;
    Eigen::Map<RowMajor2x7>{jacobians[0]} = J_tangent * PoseMinusJacobian(T_w_b);
  }
  if (want_extrinsic) {
    const Eigen::Matrix<double, 2, 6> J_tangent = d_r_d_Lc * d_Lc_d_Tbc;
    Eigen::Map<RowMajor2x7>{jacobians[1]} = J_tangent * PoseMinusJacobian(T_b_c);
  }
  if (want_line) {
    const Eigen::Matrix<double, 2, 4> J_tangent = d_r_d_Lc * d_Lc_d_Lb * d_Lb_d_Lw * d_Lw_d_delta;
    Eigen::Map<RowMajor2x6>{jacobians[2]} = J_tangent * LineMinusJacobian(parameters[2]);
  }
  return true;
}

}  // namespace plucker
