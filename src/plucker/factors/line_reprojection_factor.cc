#include "plucker/factors/line_reprojection_factor.h"

#include <cmath>
#include <stdexcept>

#include "plucker/factors/line_manifold.h"
#include "plucker/factors/pose_block.h"

namespace plucker {

namespace {

using RowMajor2x6 = Eigen::Matrix<double, 2, 6, Eigen::RowMajor>;

// The pose block as T_a_b (pose_block::Read) and its inverse T_b_a.
bool ReadPose(const double* x, SE3d* T_a_b, SE3d* T_b_a) {
  Eigen::Quaterniond q;
  Eigen::Vector3d t;
  if (!pose_block::Read(x, &q, nullptr, &t)) return false;
  *T_a_b = SE3d(q, t);
  *T_b_a = T_a_b->Inverse();
  return true;
}

// Writes the ambient 2x7 Jacobian of a pose block from its 2x6 tangent Jacobian.
void WritePoseJacobian(const Eigen::Matrix<double, 2, 6>& J, const SE3d& T, double* jacobian) {
  pose_block::WriteAmbient<2>(J.leftCols<3>(), J.rightCols<3>(), T.rotation(), jacobian);
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
  const bool want_pose = jacobians && jacobians[0];
  const bool want_line = jacobians && jacobians[1];
  SE3d T_w_c, T_c_w;
  if (!ReadPose(parameters[0], &T_w_c, &T_c_w) || !IsUsableLineBlock(parameters[1])) return false;
  const OrthonormalLine line = OrthonormalLine::FromParameters(parameters[1]);

  Eigen::Matrix<double, 6, 4> d_Lw_d_delta;
  const Line6d L_w = PluckerFromOrthonormal(line, want_line ? &d_Lw_d_delta : nullptr);
  Matrix6d d_Lc_d_Lw, d_Lc_d_Twc;
  const Line6d L_c = TransformLine(T_c_w, L_w, nullptr, want_line ? &d_Lc_d_Lw : nullptr,
                                   want_pose ? &d_Lc_d_Twc : nullptr);
  Eigen::Matrix<double, 2, 6> d_r_d_Lc;
  if (!ResidualFromCameraLine(obs_, L_c, residuals, jacobians ? &d_r_d_Lc : nullptr)) {
    return false;
  }
  if (want_pose) {
    WritePoseJacobian(d_r_d_Lc * d_Lc_d_Twc, T_w_c, jacobians[0]);
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
  const bool want_body = jacobians && jacobians[0];
  const bool want_extrinsic = jacobians && jacobians[1];
  const bool want_line = jacobians && jacobians[2];
  SE3d T_w_b, T_b_w, T_b_c, T_c_b;
  if (!ReadPose(parameters[0], &T_w_b, &T_b_w) || !ReadPose(parameters[1], &T_b_c, &T_c_b) ||
      !IsUsableLineBlock(parameters[2])) {
    return false;
  }
  const OrthonormalLine line = OrthonormalLine::FromParameters(parameters[2]);

  Eigen::Matrix<double, 6, 4> d_Lw_d_delta;
  const Line6d L_w = PluckerFromOrthonormal(line, want_line ? &d_Lw_d_delta : nullptr);
  Matrix6d d_Lb_d_Lw, d_Lb_d_Twb, d_Lc_d_Lb, d_Lc_d_Tbc;
  const Line6d L_b = TransformLine(T_b_w, L_w, nullptr, want_line ? &d_Lb_d_Lw : nullptr,
                                   want_body ? &d_Lb_d_Twb : nullptr);
  const Line6d L_c =
      TransformLine(T_c_b, L_b, nullptr, (want_body || want_line) ? &d_Lc_d_Lb : nullptr,
                    want_extrinsic ? &d_Lc_d_Tbc : nullptr);
  Eigen::Matrix<double, 2, 6> d_r_d_Lc;
  if (!ResidualFromCameraLine(obs_, L_c, residuals, jacobians ? &d_r_d_Lc : nullptr)) {
    return false;
  }
  if (want_body) {
    WritePoseJacobian(d_r_d_Lc * d_Lc_d_Lb * d_Lb_d_Twb, T_w_b, jacobians[0]);
  }
  if (want_extrinsic) {
    WritePoseJacobian(d_r_d_Lc * d_Lc_d_Tbc, T_b_c, jacobians[1]);
  }
  if (want_line) {
    const Eigen::Matrix<double, 2, 4> J_tangent = d_r_d_Lc * d_Lc_d_Lb * d_Lb_d_Lw * d_Lw_d_delta;
    Eigen::Map<RowMajor2x6>{jacobians[2]} = J_tangent * LineMinusJacobian(parameters[2]);
  }
  return true;
}

}  // namespace plucker
