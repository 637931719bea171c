#include "plucker/geometry/point_triangulation.h"

#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "plucker/geometry/point_projection.h"

namespace plucker {

namespace {

using Status = PointTriangulationStatus;

PointTriangulationResult Fail(PointTriangulationResult r, Status status, const std::string& msg) {
  r.status = status;
  r.message = std::string(ToString(status)) + ": " + msg;
  return r;
}

// Two unit vectors completing the unit vector f to an orthonormal basis.
void OrthonormalComplement(const Eigen::Vector3d& f, Eigen::Vector3d* e1, Eigen::Vector3d* e2) {
  const Eigen::Vector3d a =
      std::abs(f.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  *e1 = f.cross(a).normalized();
  *e2 = f.cross(*e1);
}

// Sum of squared reprojection errors; false when a projection fails (behind a camera).
bool Cost(const PinholeIntrinsics& K, const std::vector<SE3d>& T_w_c,
          const std::vector<Eigen::Vector2d>& uv, const Eigen::Vector3d& p_w, double min_depth,
          double* cost, Eigen::Matrix3d* H = nullptr, Eigen::Vector3d* g = nullptr) {
  *cost = 0.0;
  if (H) H->setZero();
  if (g) g->setZero();
  Eigen::Matrix<double, 2, 3> J;
  for (std::size_t i = 0; i < uv.size(); ++i) {
    const auto proj = ProjectPoint(K, T_w_c[i], p_w, nullptr, H ? &J : nullptr, min_depth);
    if (!proj) return false;
    const Eigen::Vector2d r = *proj - uv[i];
    *cost += r.squaredNorm();
    if (H) {
      *H += J.transpose() * J;
      *g += J.transpose() * r;
    }
  }
  return std::isfinite(*cost);
}

double Rms(double cost, std::size_t n) { return std::sqrt(cost / static_cast<double>(n)); }

}  // namespace

const char* ToString(PointTriangulationStatus status) {
  switch (status) {
    case Status::kOk:
      return "ok";
    case Status::kInvalidInput:
      return "invalid input";
    case Status::kTooFewViews:
      return "too few views";
    case Status::kSmallParallax:
      return "small parallax";
    case Status::kDegenerate:
      return "degenerate";
    case Status::kBehindCamera:
      return "behind camera";
    case Status::kNotConverged:
      return "not converged";
  }
  return "unknown";
}

PointTriangulationResult TriangulatePoint(const PinholeIntrinsics& K,
                                          const std::vector<SE3d>& T_w_c,
                                          const std::vector<Eigen::Vector2d>& uv,
                                          const PointTriangulationOptions& options) {
  PointTriangulationResult res;
  if (!K.IsValid()) return Fail(res, Status::kInvalidInput, "invalid intrinsics");
  if (T_w_c.size() != uv.size()) return Fail(res, Status::kInvalidInput, "pose/pixel count differ");
  const std::size_t n = uv.size();
  if (static_cast<int>(n) < std::max(2, options.min_views)) {
    return Fail(res, Status::kTooFewViews, std::to_string(n) + " views");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!uv[i].allFinite() || !T_w_c[i].translation().allFinite() ||
        !T_w_c[i].rotation().coeffs().allFinite()) {
      return Fail(res, Status::kInvalidInput, "non-finite input in view " + std::to_string(i));
    }
  }

  // Bearings (world frame) and the largest pairwise angle between them.
  std::vector<Eigen::Vector3d> f_c(n), f_w(n);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    f_c[i] = K.ToNormalized<double>(uv[i]).homogeneous().normalized();
    f_w[i] = T_w_c[i].rotation() * f_c[i];
    centroid += T_w_c[i].translation();
  }
  centroid /= static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      // Angle between the two rays as lines, in [0, pi/2]: opposite rays (cameras facing each
      // other across the point) are as collinear as parallel ones.
      const double angle = std::atan2(f_w[i].cross(f_w[j]).norm(), std::abs(f_w[i].dot(f_w[j])));
      res.max_parallax_rad = std::max(res.max_parallax_rad, angle);
    }
  }
  const double min_parallax = options.min_parallax_deg * M_PI / 180.0;
  if (!(res.max_parallax_rad >= min_parallax)) {
    std::ostringstream msg;
    msg << "max parallax " << res.max_parallax_rad * 180.0 / M_PI << " deg < "
        << options.min_parallax_deg << " deg";
    return Fail(res, Status::kSmallParallax, msg.str());
  }

  // Normalisation: camera centres centred at the origin with RMS distance 1.
  double scale = 0.0;
  for (const SE3d& T : T_w_c) scale += (T.translation() - centroid).squaredNorm();
  scale = std::sqrt(scale / static_cast<double>(n));
  if (!(scale > 1e-12 * (1.0 + centroid.norm()))) {
    return Fail(res, Status::kDegenerate, "all camera centres coincide (zero baseline)");
  }

  // DLT: the point X = centroid + scale * x / w lies on ray i when e_k . (R_i^T (X - t_i)) = 0 for
  // the two unit vectors e_1, e_2 orthogonal to the bearing f_c[i].
  Eigen::MatrixXd A(2 * n, 4);
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Vector3d e[2];
    OrthonormalComplement(f_c[i], &e[0], &e[1]);
    const Eigen::Matrix3d Rt = T_w_c[i].RotationMatrix().transpose();
    for (int k = 0; k < 2; ++k) {
      const Eigen::RowVector3d a = e[k].transpose() * Rt;
      A.block<1, 3>(2 * i + k, 0) = scale * a;
      A(2 * i + k, 3) = a * (centroid - T_w_c[i].translation());
    }
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector4d X = svd.matrixV().col(3);
  if (!X.allFinite() || !(std::abs(X(3)) > 1e-12 * X.head<3>().norm())) {
    return Fail(res, Status::kDegenerate, "linear solution at infinity");
  }
  Eigen::Vector3d p_w = centroid + scale * X.head<3>() / X(3);
  res.p_w = p_w;

  double cost = 0.0;
  if (!Cost(K, T_w_c, uv, p_w, options.min_depth, &cost)) {
    return Fail(res, Status::kBehindCamera, "linear solution not in front of every camera");
  }
  res.initial_rms_px = res.final_rms_px = Rms(cost, n);
  if (!options.refine) {
    res.status = Status::kOk;
    return res;
  }

  // Gauss-Newton with step halving (keeps the point in front of the cameras, cost non-increasing).
  bool converged = false;
  for (int it = 0; it < options.max_iterations && !converged; ++it) {
    res.iterations = it + 1;
    Eigen::Matrix3d H;
    Eigen::Vector3d g;
    Cost(K, T_w_c, uv, p_w, options.min_depth, &cost, &H, &g);
    if (cost <= 1e-30) {
      converged = true;
      break;
    }
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(H);
    const Eigen::Vector3d dx = -ldlt.solve(g);
    if (ldlt.info() != Eigen::Success || !dx.allFinite()) break;
    double alpha = 1.0, new_cost = 0.0;
    bool accepted = false;
    for (int k = 0; k < 12 && !accepted; ++k, alpha *= 0.5) {
      accepted =
          Cost(K, T_w_c, uv, p_w + alpha * dx, options.min_depth, &new_cost) && new_cost <= cost;
      if (accepted) break;
    }
    if (!accepted) {
      // No decrease along the Gauss-Newton direction: at a minimum up to rounding.
      converged = true;
      break;
    }
    p_w += alpha * dx;
    converged = alpha * dx.norm() <= options.step_tolerance * (1.0 + p_w.norm()) ||
                (cost - new_cost) <= options.cost_tolerance * cost;
    cost = new_cost;
  }
  res.p_w = p_w;
  res.final_rms_px = Rms(cost, n);
  if (!Cost(K, T_w_c, uv, p_w, options.min_depth, &cost)) {
    return Fail(res, Status::kBehindCamera, "refined point not in front of every camera");
  }
  if (!converged) {
    return Fail(res, Status::kNotConverged,
                std::to_string(options.max_iterations) + " Gauss-Newton iterations");
  }
  res.status = Status::kOk;
  return res;
}

}  // namespace plucker
