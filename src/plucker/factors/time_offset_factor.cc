#include "plucker/factors/time_offset_factor.h"

#include <ceres/autodiff_cost_function.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "plucker/factors/line_reprojection_factor.h"
#include "plucker/geometry/line_projection.h"
#include "plucker/geometry/orthonormal_line.h"
#include "plucker/geometry/point_projection.h"
#include "plucker/geometry/se3.h"

namespace plucker {
namespace {

void CheckVelocity(const Eigen::Vector2d& v) {
  if (!v.allFinite()) throw std::invalid_argument("time offset factor: non-finite image velocity");
}

// The autodiff twin of the point factor, written on its own: r = S (pi(p_c) - (uv - td v)).
struct PointTimeOffsetResidual {
  PointObservation obs;
  Eigen::Vector2d v;
  template <typename T>
  bool operator()(const T* T_w_b, const T* T_b_c, const T* td, const T* p_w, T* residual) const {
    const SE3<T> T_w_c = SE3<T>::FromParameters(T_w_b) * SE3<T>::FromParameters(T_b_c);
    Eigen::Matrix<T, 2, 1> uv;
    if (!ProjectPointT<T>(obs.K, T_w_c, Eigen::Matrix<T, 3, 1>(p_w[0], p_w[1], p_w[2]), &uv,
                          kPointMinDepth)) {
      return false;
    }
    const Eigen::Matrix<T, 2, 1> shifted = obs.uv.cast<T>() - td[0] * v.cast<T>();
    Eigen::Map<Eigen::Matrix<T, 2, 1>> r(residual);
    r = obs.sqrt_information.cast<T>() * (uv - shifted);
    return true;
  }
};

// The autodiff twin of the line factor, written on its own: the camera-frame line from the
// anchored block and T_w_c = T_w_b T_b_c moved into the anchor frame, then the signed distances of
// the shifted endpoints p - td v_p to its image line.
struct LineTimeOffsetResidual {
  LineSegmentMeasurement m;
  Eigen::Vector2d v_s, v_e;
  LineAnchor anchor;
  template <typename T>
  bool operator()(const T* T_w_b, const T* T_b_c, const T* td, const T* line, T* residual) const {
    using namespace line_factor_internal;
    if (HasZeroQuaternion(T_w_b) || HasZeroQuaternion(T_b_c) || IsDegenerateLineBlock(line)) {
      return false;
    }
    const SE3<T> T_w_c = SE3<T>::FromParameters(T_w_b) * SE3<T>::FromParameters(T_b_c);
    const SE3<T> T_a_c(T_w_c.rotation(),
                       (T_w_c.translation() - anchor.c_w.cast<T>()) / T(anchor.scale));
    const Line6<T> L_c = TransformLine<T>(T_a_c.Inverse(), PluckerFromOrthonormal<T>(line));
    if (LineThroughCameraCentre<T>(L_c)) return false;
    const Eigen::Matrix<T, 3, 1> l = ProjectLinePixels<T>(m.K_line, L_c);
    const T rho_sq = l(0) * l(0) + l(1) * l(1);
    const double ratio_sq = kMinImageLineNormalRatio * kMinImageLineNormalRatio;
    if (!(rho_sq > T(ratio_sq) * (rho_sq + l(2) * l(2)))) return false;
    const Eigen::Matrix<T, 2, 1> s = m.s_px.cast<T>() - td[0] * v_s.cast<T>();
    const Eigen::Matrix<T, 2, 1> e = m.e_px.cast<T>() - td[0] * v_e.cast<T>();
    using std::sqrt;
    const T inv_rho = T(1) / sqrt(rho_sq);
    Eigen::Matrix<T, 2, 1> d;
    d(0) = (s(0) * l(0) + s(1) * l(1) + l(2)) * inv_rho;
    d(1) = (e(0) * l(0) + e(1) * l(1) + l(2)) * inv_rho;
    Eigen::Map<Eigen::Matrix<T, 2, 1>> r(residual);
    r = m.sqrt_information.cast<T>() * d;
    return true;
  }
};

// tau for the shifted segment: 1 s, or less so that it keeps at least half the segment's length.
double ShiftTau(const Eigen::Vector2d& s_px, const Eigen::Vector2d& e_px,
                const Eigen::Vector2d& v_s, const Eigen::Vector2d& v_e) {
  const double dv = (v_e - v_s).norm();
  const double length = (e_px - s_px).norm();
  return dv > 0.5 * length ? 0.5 * length / dv : 1.0;
}

}  // namespace

// ---------------------------------------------------------------- point

ceres::CostFunction* PointReprojectionFactorVITimeOffset::Create(
    const PinholeIntrinsics& K, const Eigen::Vector2d& uv, const Eigen::Vector2d& uv_velocity,
    const Eigen::Matrix2d& sqrt_information) {
  CheckVelocity(uv_velocity);
  const PointObservation obs = MakePointObservation(K, uv, sqrt_information);
  return new PointReprojectionFactorVITimeOffset(
      PointReprojectionFactorVI::Create(K, uv, sqrt_information),
      obs.sqrt_information * uv_velocity);
}

ceres::CostFunction* PointReprojectionFactorVITimeOffset::CreateAutoDiff(
    const PinholeIntrinsics& K, const Eigen::Vector2d& uv, const Eigen::Vector2d& uv_velocity,
    const Eigen::Matrix2d& sqrt_information) {
  CheckVelocity(uv_velocity);
  return new ceres::AutoDiffCostFunction<PointTimeOffsetResidual, 2, 7, 7, 1, 3>(
      new PointTimeOffsetResidual{MakePointObservation(K, uv, sqrt_information), uv_velocity});
}

bool PointReprojectionFactorVITimeOffset::Evaluate(double const* const* parameters,
                                                   double* residuals, double** jacobians) const {
  const double td = parameters[2][0];
  if (!std::isfinite(td)) return false;
  const double* vi_parameters[3] = {parameters[0], parameters[1], parameters[3]};
  double* vi_jacobians[3] = {jacobians ? jacobians[0] : nullptr, jacobians ? jacobians[1] : nullptr,
                             jacobians ? jacobians[3] : nullptr};
  if (!vi_->Evaluate(vi_parameters, residuals, jacobians ? vi_jacobians : nullptr)) return false;
  // r = r(uv) + td S v: the measurement enters additively, the other Jacobians are unchanged.
  Eigen::Map<Eigen::Vector2d>{residuals} += td * S_v_;
  if (jacobians && jacobians[2]) Eigen::Map<Eigen::Vector2d>{jacobians[2]} = S_v_;
  return true;
}

// ---------------------------------------------------------------- line

ceres::CostFunction* AnchoredLineFactorVITimeOffset::Create(
    const PinholeIntrinsics& K, const Eigen::Vector2d& s_px, const Eigen::Vector2d& e_px,
    const Eigen::Vector2d& s_velocity, const Eigen::Vector2d& e_velocity,
    const Eigen::Matrix2d& sqrt_information, const LineAnchor& anchor) {
  CheckVelocity(s_velocity);
  CheckVelocity(e_velocity);
  std::unique_ptr<ceres::CostFunction> at(
      AnchoredLineFactorVI::Create(K, s_px, e_px, sqrt_information, anchor));
  const double tau = ShiftTau(s_px, e_px, s_velocity, e_velocity);
  ceres::CostFunction* shifted = AnchoredLineFactorVI::Create(
      K, s_px - tau * s_velocity, e_px - tau * e_velocity, sqrt_information, anchor);
  return new AnchoredLineFactorVITimeOffset(at.release(), shifted, tau);
}

ceres::CostFunction* AnchoredLineFactorVITimeOffset::CreateAutoDiff(
    const PinholeIntrinsics& K, const Eigen::Vector2d& s_px, const Eigen::Vector2d& e_px,
    const Eigen::Vector2d& s_velocity, const Eigen::Vector2d& e_velocity,
    const Eigen::Matrix2d& sqrt_information, const LineAnchor& anchor) {
  CheckVelocity(s_velocity);
  CheckVelocity(e_velocity);
  // The anchor is validated by the analytic factor's constructor.
  delete AnchoredLineFactor::Create(K, s_px, e_px, sqrt_information, anchor);
  return new ceres::AutoDiffCostFunction<LineTimeOffsetResidual, 2, 7, 7, 1, 6>(
      new LineTimeOffsetResidual{MakeLineSegmentMeasurement(K, s_px, e_px, sqrt_information),
                                 s_velocity, e_velocity, anchor});
}

bool AnchoredLineFactorVITimeOffset::Evaluate(double const* const* parameters, double* residuals,
                                              double** jacobians) const {
  const double td = parameters[2][0];
  if (!std::isfinite(td)) return false;
  const double* vi_parameters[3] = {parameters[0], parameters[1], parameters[3]};
  Eigen::Vector2d r_a, r_b;
  Eigen::Matrix<double, 2, 7, Eigen::RowMajor> Jb_a, Jb_b, Jbc_a, Jbc_b;
  Eigen::Matrix<double, 2, 6, Eigen::RowMajor> Jl_a, Jl_b;
  const bool want = jacobians != nullptr;
  double* j_a[3] = {want && jacobians[0] ? Jb_a.data() : nullptr,
                    want && jacobians[1] ? Jbc_a.data() : nullptr,
                    want && jacobians[3] ? Jl_a.data() : nullptr};
  double* j_b[3] = {j_a[0] ? Jb_b.data() : nullptr, j_a[1] ? Jbc_b.data() : nullptr,
                    j_a[2] ? Jl_b.data() : nullptr};
  if (!at_->Evaluate(vi_parameters, r_a.data(), want ? j_a : nullptr) ||
      !shifted_->Evaluate(vi_parameters, r_b.data(), want ? j_b : nullptr)) {
    return false;
  }
  // The residual is affine in the endpoints: interpolate (extrapolate) between the two.
  const double w = td / tau_;
  Eigen::Map<Eigen::Vector2d>{residuals} = (1.0 - w) * r_a + w * r_b;
  if (!want) return true;
  if (jacobians[0]) {
    Eigen::Map<Eigen::Matrix<double, 2, 7, Eigen::RowMajor>>{jacobians[0]} =
        (1.0 - w) * Jb_a + w * Jb_b;
  }
  if (jacobians[1]) {
    Eigen::Map<Eigen::Matrix<double, 2, 7, Eigen::RowMajor>>{jacobians[1]} =
        (1.0 - w) * Jbc_a + w * Jbc_b;
  }
  if (jacobians[3]) {
    Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>>{jacobians[3]} =
        (1.0 - w) * Jl_a + w * Jl_b;
  }
  if (jacobians[2]) Eigen::Map<Eigen::Vector2d>{jacobians[2]} = (r_b - r_a) / tau_;
  return true;
}

}  // namespace plucker
