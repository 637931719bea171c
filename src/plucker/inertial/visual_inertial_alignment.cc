#include "plucker/inertial/visual_inertial_alignment.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "plucker/geometry/so3.h"
#include "plucker/inertial/gravity.h"

namespace plucker {
namespace inertial {
namespace {

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

// Keyframe k in c0: body rotation R_c0_bk and the visual (up-to-scale) camera position.
struct Keyframe {
  Matrix3d R_c0_b;
  Vector3d p_bar;
};

std::vector<Keyframe> Keyframes(const AlignmentInput& in) {
  const Matrix3d R_c_b = in.T_b_c.RotationMatrix().transpose();
  std::vector<Keyframe> k;
  for (const SE3d& T : in.T_c0_ck) k.push_back({T.RotationMatrix() * R_c_b, T.translation()});
  return k;
}

void Validate(const AlignmentInput& in, const AlignmentOptions& o) {
  if (in.T_c0_ck.empty() || in.preintegrations.size() + 1 != in.T_c0_ck.size()) {
    throw std::invalid_argument("AlignVisualInertial: " + std::to_string(in.T_c0_ck.size()) +
                                " keyframe poses and " + std::to_string(in.preintegrations.size()) +
                                " preintegrations (one fewer than the poses is needed)");
  }
  for (const SE3d& T : in.T_c0_ck) {
    if (!T.translation().allFinite() || !T.rotation().coeffs().allFinite()) {
      throw std::invalid_argument("AlignVisualInertial: a keyframe pose is not finite");
    }
  }
  if (!in.T_b_c.translation().allFinite() || !in.T_b_c.rotation().coeffs().allFinite()) {
    throw std::invalid_argument("AlignVisualInertial: the extrinsic T_b_c is not finite");
  }
  if (!(o.gravity_magnitude > 0 && o.max_gravity_deviation > 0 && o.max_scale_relative_sigma > 0 &&
        o.visual_position_sigma >= 0 && o.max_whitened_rms > 0 && o.max_accel_bias_sigmas > 0 &&
        o.gyro_bias_iterations >= 1 && o.gravity_iterations >= 1 && o.min_keyframes >= 3)) {
    throw std::invalid_argument("AlignVisualInertial: invalid options");
  }
}

// The stacked, whitened linear system, unknowns [v_0 .. v_{N-1}, g, s, b_a] in c0 (3N + 7).
// Rows of pair (i, j = i + 1), docs "Linear alignment", with the accelerometer bias to first
// order, Dp(b_a) = Dp + dp_dba (b_a - b_lin):
//   s (p_j - p_i) - Dt v_i - 1/2 Dt^2 g - R_i dp_dba b_a = R_i (Dp - dp_dba b_lin) + (R_j - R_i)
//   t_b_c v_j - v_i - Dt g - R_i dv_dba b_a                    = R_i (Dv - dv_dba b_lin)
struct LinearSystem {
  MatrixXd A;  // whitened
  VectorXd b;
};

LinearSystem BuildSystem(const std::vector<Keyframe>& kf, const Vector3d& t_b_c,
                         const std::vector<ImuPreintegration>& pre, double visual_sigma) {
  const int n = static_cast<int>(kf.size());
  const int cols = 3 * n + 7;
  LinearSystem sys;
  sys.A = MatrixXd::Zero(6 * (n - 1), cols);
  sys.b = VectorXd::Zero(6 * (n - 1));
  const int g_col = 3 * n, s_col = 3 * n + 3, ba_col = 3 * n + 4;
  for (int i = 0; i + 1 < n; ++i) {
    const int j = i + 1;
    const ImuPreintegration& p = pre[i];
    const double dt = p.Dt();
    const Matrix3d& Ri = kf[i].R_c0_b;
    const Vector3d& b_lin = p.BiasLinearisation().accel;
    Eigen::Matrix<double, 6, Eigen::Dynamic> rows =
        Eigen::Matrix<double, 6, Eigen::Dynamic>::Zero(6, cols);
    Eigen::Matrix<double, 6, 1> rhs;
    rows.block<3, 3>(0, 3 * i) = -dt * Matrix3d::Identity();
    rows.block<3, 3>(0, g_col) = -0.5 * dt * dt * Matrix3d::Identity();
    rows.block<3, 1>(0, s_col) = kf[j].p_bar - kf[i].p_bar;
    rows.block<3, 3>(0, ba_col) = -Ri * p.d_p_d_ba();
    rhs.head<3>() = Ri * (p.DeltaP() - p.d_p_d_ba() * b_lin) + (kf[j].R_c0_b - Ri) * t_b_c;
    rows.block<3, 3>(3, 3 * i) = -Matrix3d::Identity();
    rows.block<3, 3>(3, 3 * j) = Matrix3d::Identity();
    rows.block<3, 3>(3, g_col) = -dt * Matrix3d::Identity();
    rows.block<3, 3>(3, ba_col) = -Ri * p.d_v_d_ba();
    rhs.tail<3>() = Ri * (p.DeltaV() - p.d_v_d_ba() * b_lin);
    // Covariance of [p-row; v-row]: the preintegration's [dp, dv] blocks rotated into c0, and
    // the noise of the two visual positions.
    const Matrix9d C = p.Covariance();  // order [dtheta, dv, dp]
    Eigen::Matrix<double, 6, 6> S;
    S.block<3, 3>(0, 0) = Ri * C.block<3, 3>(6, 6) * Ri.transpose();
    S.block<3, 3>(0, 3) = Ri * C.block<3, 3>(6, 3) * Ri.transpose();
    S.block<3, 3>(3, 0) = S.block<3, 3>(0, 3).transpose();
    S.block<3, 3>(3, 3) = Ri * C.block<3, 3>(3, 3) * Ri.transpose();
    S.block<3, 3>(0, 0) += 2.0 * visual_sigma * visual_sigma * Matrix3d::Identity();
    const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(S);
    sys.A.middleRows<6>(6 * i) = llt.matrixL().solve(rows);
    sys.b.segment<6>(6 * i) = llt.matrixL().solve(rhs);
  }
  return sys;
}

// Least squares with Jacobi column scaling; false when the normal matrix is rank-deficient.
bool SolveLeastSquares(const MatrixXd& A, const VectorXd& b, VectorXd* x, MatrixXd* covariance) {
  const MatrixXd M = A.transpose() * A;
  const VectorXd d = M.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const MatrixXd Ms = d.asDiagonal() * M * d.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<MatrixXd> eig(Ms);
  const VectorXd& ev = eig.eigenvalues();
  if (!(ev.minCoeff() > 1e-12 * ev.maxCoeff())) return false;
  const MatrixXd Ms_inv =
      eig.eigenvectors() * ev.cwiseInverse().asDiagonal() * eig.eigenvectors().transpose();
  *covariance = d.asDiagonal() * Ms_inv * d.asDiagonal();
  *x = *covariance * (A.transpose() * b);
  return true;
}

std::string Format(const char* fmt, double a, double b, double c = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof(buf), fmt, a, b, c);
  return buf;
}

}  // namespace

const char* ToString(AlignmentStatus status) {
  switch (status) {
    case AlignmentStatus::kSuccess:
      return "success";
    case AlignmentStatus::kTooFewKeyframes:
      return "too few keyframes";
    case AlignmentStatus::kNotExcited:
      return "too little excitation";
    case AlignmentStatus::kNonPositiveScale:
      return "non-positive scale";
    case AlignmentStatus::kGravityMagnitude:
      return "gravity magnitude";
    case AlignmentStatus::kInconsistent:
      return "inconsistent";
  }
  return "unknown";
}

Eigen::Vector3d EstimateGyroBias(const std::vector<SE3d>& T_c0_ck, const SE3d& T_b_c,
                                 const std::vector<ImuPreintegration>& pre) {
  if (pre.empty() || pre.size() + 1 != T_c0_ck.size()) {
    throw std::invalid_argument("EstimateGyroBias: N poses need N - 1 > 0 preintegrations");
  }
  const Matrix3d R_c_b = T_b_c.RotationMatrix().transpose();
  Matrix3d H = Matrix3d::Zero();
  Vector3d g = Vector3d::Zero();
  for (std::size_t i = 0; i < pre.size(); ++i) {
    const Matrix3d R_i = T_c0_ck[i].RotationMatrix() * R_c_b;
    const Matrix3d R_j = T_c0_ck[i + 1].RotationMatrix() * R_c_b;
    const Matrix3d R_bi_bj = R_i.transpose() * R_j;
    // J (b - b_lin) = Log(DR^T R_bi_bj)  <=>  J b = Log(...) + J b_lin.
    const Matrix3d& J = pre[i].d_R_d_bg();
    const Vector3d r = LogSO3<double>(Eigen::Quaterniond(pre[i].DeltaR().transpose() * R_bi_bj)) +
                       J * pre[i].BiasLinearisation().gyro;
    H += J.transpose() * J;
    g += J.transpose() * r;
  }
  return H.ldlt().solve(g);
}

AlignmentResult AlignVisualInertial(const AlignmentInput& in, const AlignmentOptions& o) {
  Validate(in, o);
  AlignmentResult r;
  const int n = static_cast<int>(in.T_c0_ck.size());
  if (n < o.min_keyframes) {
    r.status = AlignmentStatus::kTooFewKeyframes;
    r.message = Format("%.0f keyframes, %.0f are needed", n, o.min_keyframes);
    return r;
  }
  const std::vector<Keyframe> kf = Keyframes(in);
  const Vector3d t_b_c = in.T_b_c.translation();

  // (a) Gyro bias, integrating again at each estimate.
  r.preintegrations = in.preintegrations;
  r.bias = r.preintegrations.front().BiasLinearisation();
  for (int it = 0; it < o.gyro_bias_iterations; ++it) {
    r.bias.gyro = EstimateGyroBias(in.T_c0_ck, in.T_b_c, r.preintegrations);
    for (ImuPreintegration& p : r.preintegrations) {
      p.Repropagate({r.bias.gyro, p.BiasLinearisation().accel});
    }
  }

  // (b) Velocities, gravity and scale.
  const LinearSystem sys = BuildSystem(kf, t_b_c, r.preintegrations, o.visual_position_sigma);
  const int g_col = 3 * n, s_col = 3 * n + 3, ba_col = 3 * n + 4;
  const Vector3d ba_prior = r.bias.accel;  // the accelerometer bias is held here in (b)
  r.rows = static_cast<int>(sys.A.rows());
  r.unknowns = 3 * n + 4;
  VectorXd x;
  MatrixXd cov;
  if (!SolveLeastSquares(sys.A.leftCols(3 * n + 4), sys.b - sys.A.middleCols<3>(ba_col) * ba_prior,
                         &x, &cov)) {
    r.status = AlignmentStatus::kNotExcited;
    r.message = "velocities, gravity and scale are not separable (constant-velocity motion?)";
    return r;
  }
  Vector3d g = x.segment<3>(g_col);
  r.scale = x(s_col);
  r.gravity_norm_unrefined = g.norm();
  if (!(r.scale > 0)) {
    r.status = AlignmentStatus::kNonPositiveScale;
    r.message = Format("scale %.4g after the linear solve (|g| %.3f m/s^2)", r.scale, g.norm());
    return r;
  }
  if (!(std::abs(g.norm() - o.gravity_magnitude) <= o.max_gravity_deviation)) {
    r.status = AlignmentStatus::kGravityMagnitude;
    r.message = Format("|g| = %.3f m/s^2 after the linear solve, expected %.3f", g.norm(),
                       o.gravity_magnitude);
    return r;
  }

  // (c) Gravity on the sphere, g = g0 + B w with |g0| = |g| and B a tangent basis at g0; the
  // accelerometer bias with a prior N(ba_prior, sigma^2 I) (three extra rows), or held.
  const bool with_ba = o.accel_bias_prior_sigma > 0;
  const int cols = 3 * n + 3 + (with_ba ? 3 : 0);
  const int rows = static_cast<int>(sys.A.rows()) + (with_ba ? 3 : 0);
  MatrixXd A_c = MatrixXd::Zero(rows, cols);
  VectorXd b_c = VectorXd::Zero(rows);
  for (int it = 0; it < o.gravity_iterations; ++it) {
    const Vector3d g0 = g.normalized() * o.gravity_magnitude;
    const Eigen::Matrix<double, 3, 2> B = TangentBasis(g.normalized());
    const int m = static_cast<int>(sys.A.rows());
    A_c.topLeftCorner(m, 3 * n) = sys.A.leftCols(3 * n);
    A_c.block(0, 3 * n, m, 2) = sys.A.middleCols<3>(g_col) * B;
    A_c.block(0, 3 * n + 2, m, 1) = sys.A.col(s_col);
    b_c.head(m) = sys.b - sys.A.middleCols<3>(g_col) * g0;
    if (with_ba) {
      A_c.block(0, 3 * n + 3, m, 3) = sys.A.middleCols<3>(ba_col);
      A_c.block<3, 3>(m, 3 * n + 3) = Matrix3d::Identity() / o.accel_bias_prior_sigma;
      b_c.tail<3>() = ba_prior / o.accel_bias_prior_sigma;
    } else {
      b_c.head(m) -= sys.A.middleCols<3>(ba_col) * ba_prior;
    }
    if (!SolveLeastSquares(A_c, b_c, &x, &cov)) {
      r.status = AlignmentStatus::kNotExcited;
      r.message = "velocities, gravity direction and scale are not separable";
      return r;
    }
    g = (g0 + B * x.segment<2>(3 * n)).normalized() * o.gravity_magnitude;
    r.whitened_rms = std::sqrt((A_c * x - b_c).squaredNorm() / static_cast<double>(rows));
  }
  r.rows = rows;
  r.unknowns = cols;
  if (with_ba) r.bias.accel = x.segment<3>(3 * n + 3);
  r.scale = x(3 * n + 2);
  r.scale_sigma = std::sqrt(cov(3 * n + 2, 3 * n + 2));
  r.gravity_c0 = g;
  if (!(r.scale > 0)) {
    r.status = AlignmentStatus::kNonPositiveScale;
    r.message =
        Format("scale %.4g after the gravity refinement (sigma %.3g)", r.scale, r.scale_sigma);
    return r;
  }
  if (!(r.whitened_rms <= o.max_whitened_rms)) {
    r.status = AlignmentStatus::kInconsistent;
    r.message = Format(
        "the whitened residuals' rms is %.3g, at most %.3g allowed: the visual "
        "poses and the IMU disagree",
        r.whitened_rms, o.max_whitened_rms);
    return r;
  }
  const double bias_sigmas =
      with_ba ? (r.bias.accel - ba_prior).norm() / o.accel_bias_prior_sigma : 0.0;
  if (!(bias_sigmas <= o.max_accel_bias_sigmas)) {
    r.status = AlignmentStatus::kInconsistent;
    r.message = Format(
        "the accelerometer bias is %.3g m/s^2, %.3g sigmas of its prior, at most %.3g allowed: the "
        "visual poses and the IMU disagree",
        (r.bias.accel - ba_prior).norm(), bias_sigmas, o.max_accel_bias_sigmas);
    return r;
  }
  if (!(r.scale_sigma <= o.max_scale_relative_sigma * r.scale)) {
    r.status = AlignmentStatus::kNotExcited;
    r.message = Format("the scale's standard deviation is %.3g of the scale, at most %.3g allowed",
                       r.scale_sigma / r.scale, o.max_scale_relative_sigma);
    return r;
  }

  for (ImuPreintegration& p : r.preintegrations) p.Repropagate(r.bias);

  // World frame: gravity along -z, the first body frame's yaw zero.
  const Vector3d up_b0 = -(kf[0].R_c0_b.transpose() * g);
  r.R_w_c0 = GravityAlignedRotation(up_b0) * kf[0].R_c0_b.transpose();
  double t = in.t0;
  for (int k = 0; k < n; ++k) {
    if (k > 0) t += r.preintegrations[k - 1].Dt();
    const Vector3d p_c0_b = r.scale * kf[k].p_bar - kf[k].R_c0_b * t_b_c;
    r.states.push_back({t, SE3d(r.R_w_c0 * kf[k].R_c0_b, r.R_w_c0 * p_c0_b),
                        r.R_w_c0 * x.segment<3>(3 * k), r.bias});
  }
  r.status = AlignmentStatus::kSuccess;
  return r;
}

}  // namespace inertial
}  // namespace plucker
