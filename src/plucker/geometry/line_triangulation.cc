#include "plucker/geometry/line_triangulation.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "plucker/geometry/line_projection.h"
#include "plucker/geometry/orthonormal_line.h"

namespace plucker {

namespace {

using Status = LineTriangulationStatus;

double Deg(double rad) { return rad * 180.0 / M_PI; }

LineTriangulationResult Fail(LineTriangulationResult r, Status status, const std::string& msg) {
  r.status = status;
  r.message = std::string(ToString(status)) + ": " + msg;
  return r;
}

bool IsFinite(const LineObservation& o) {
  return o.start.allFinite() && o.end.allFinite() && o.T_w_c.translation().allFinite() &&
         o.T_w_c.rotation().coeffs().allFinite();
}

// Back-projected planes of every observation; on failure sets *result and returns false.
bool Planes(const PinholeIntrinsics& K, const std::vector<LineObservation>& obs,
            const LineTriangulationOptions& options, std::vector<Eigen::Vector4d>* planes,
            LineTriangulationResult* result) {
  if (!K.IsValid()) {
    *result = Fail(*result, Status::kInvalidInput, "invalid intrinsics");
    return false;
  }
  planes->clear();
  for (std::size_t i = 0; i < obs.size(); ++i) {
    if (!IsFinite(obs[i])) {
      *result =
          Fail(*result, Status::kInvalidInput, "non-finite input in view " + std::to_string(i));
      return false;
    }
    const auto pi = BackProjectSegment(K, obs[i].T_w_c, obs[i].start, obs[i].end,
                                       options.min_segment_length_px);
    if (!pi) {
      *result = Fail(*result, Status::kInvalidInput,
                     "segment of view " + std::to_string(i) + " shorter than " +
                         std::to_string(options.min_segment_length_px) + " px");
      return false;
    }
    planes->push_back(*pi);
  }
  return true;
}

// Pairwise plane angles; kSmallParallax when the largest is below the minimum.
bool ParallaxOk(const std::vector<Eigen::Vector4d>& planes, const LineTriangulationOptions& options,
                LineTriangulationResult* result) {
  result->min_parallax_rad = M_PI / 2;
  result->max_parallax_rad = 0.0;
  for (std::size_t i = 0; i < planes.size(); ++i) {
    for (std::size_t j = i + 1; j < planes.size(); ++j) {
      const double a = PlaneAngle(planes[i], planes[j]);
      result->min_parallax_rad = std::min(result->min_parallax_rad, a);
      result->max_parallax_rad = std::max(result->max_parallax_rad, a);
    }
  }
  // Below ~1e-8 rad the planes are equal up to rounding and the line is undefined, whatever the
  // configured minimum.
  const double min_angle = std::max(options.min_plane_angle_deg * M_PI / 180.0, 1e-8);
  if (result->max_parallax_rad >= min_angle) return true;
  std::ostringstream msg;
  msg << "largest angle between back-projected planes " << Deg(result->max_parallax_rad)
      << " deg < " << options.min_plane_angle_deg << " deg";
  *result = Fail(*result, Status::kSmallParallax, msg.str());
  return false;
}

// Normalises L (|d| = 1), recovers the 3D segment, checks cheirality and orients d along the
// first observation's start -> end.
LineTriangulationResult Finish(const PinholeIntrinsics& K, const std::vector<LineObservation>& obs,
                               const Line6d& L_raw, const LineTriangulationOptions& options,
                               LineTriangulationResult result) {
  const double d_norm = L_raw.tail<3>().norm();
  if (!L_raw.allFinite() || !(d_norm > 1e-12 * L_raw.head<3>().norm()) || !(d_norm > 0)) {
    return Fail(result, Status::kIllConditioned, "line at infinity (zero direction)");
  }
  Line6d L = L_raw / d_norm;
  const Eigen::Vector3d p0 = L.tail<3>().cross(L.head<3>());  // closest point to the origin
  double mu_min = std::numeric_limits<double>::infinity(), mu_max = -mu_min;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const auto ends = SegmentEndpointsOnLine(K, obs[i], L);
    if (!ends) {
      return Fail(result, Status::kDegenerateEndpoint,
                  "an endpoint ray of view " + std::to_string(i) + " is parallel to the line");
    }
    if (!(ends->start_depth > options.min_depth) || !(ends->end_depth > options.min_depth)) {
      std::ostringstream msg;
      msg << "view " << i << ": endpoint depths " << ends->start_depth << ", " << ends->end_depth
          << " <= " << options.min_depth;
      return Fail(result, Status::kBehindCamera, msg.str());
    }
    double mu_s = L.tail<3>().dot(ends->start_w - p0), mu_e = L.tail<3>().dot(ends->end_w - p0);
    if (i == 0 && mu_e < mu_s) {
      L.tail<3>() = -L.tail<3>();
      L.head<3>() = -L.head<3>();  // n = p x d flips with d; p0 is unchanged
      mu_s = -mu_s;
      mu_e = -mu_e;
    }
    mu_min = std::min({mu_min, mu_s, mu_e});
    mu_max = std::max({mu_max, mu_s, mu_e});
  }
  const auto errors = LineReprojectionErrors(K, obs, L);
  if (!errors) {
    return Fail(result, Status::kDegenerateEndpoint, "the line projects to a point in a view");
  }
  result.rms_error_px = std::sqrt(errors->squaredNorm() / static_cast<double>(errors->size()));
  result.max_error_px = errors->cwiseAbs().maxCoeff();
  result.L_w = L;
  result.start_w = p0 + mu_min * L.tail<3>();
  result.end_w = p0 + mu_max * L.tail<3>();
  result.status = Status::kOk;
  result.message.clear();
  return result;
}

}  // namespace

const char* ToString(LineTriangulationStatus status) {
  switch (status) {
    case Status::kOk:
      return "ok";
    case Status::kInvalidInput:
      return "invalid input";
    case Status::kTooFewViews:
      return "too few views";
    case Status::kSmallParallax:
      return "small parallax";
    case Status::kIllConditioned:
      return "ill-conditioned";
    case Status::kBehindCamera:
      return "behind camera";
    case Status::kDegenerateEndpoint:
      return "degenerate endpoint";
  }
  return "unknown";
}

std::optional<Eigen::Vector4d> BackProjectSegment(const PinholeIntrinsics& K, const SE3d& T_w_c,
                                                  const Eigen::Vector2d& start,
                                                  const Eigen::Vector2d& end,
                                                  double min_length_px) {
  if (!K.IsValid() || !start.allFinite() || !end.allFinite() || !T_w_c.translation().allFinite() ||
      !T_w_c.rotation().coeffs().allFinite()) {
    return std::nullopt;
  }
  if (!((end - start).norm() >= min_length_px) || !((end - start).norm() > 0)) return std::nullopt;
  const Eigen::Vector3d xs = K.ToNormalized<double>(start).homogeneous();
  const Eigen::Vector3d xe = K.ToNormalized<double>(end).homogeneous();
  const Eigen::Vector3d m = T_w_c.rotation() * xs.cross(xe);
  const double norm = m.norm();
  if (!(norm > 0) || !std::isfinite(norm)) return std::nullopt;
  Eigen::Vector4d pi;
  pi.head<3>() = m / norm;
  pi(3) = -pi.head<3>().dot(T_w_c.translation());
  return pi;
}

double PlaneAngle(const Eigen::Vector4d& pi1, const Eigen::Vector4d& pi2) {
  const Eigen::Vector3d m1 = pi1.head<3>(), m2 = pi2.head<3>();
  // atan2 of |sin| and |cos| is accurate at both ends (acos is not near 0).
  return std::atan2(m1.cross(m2).norm(), std::abs(m1.dot(m2)));
}

std::optional<SegmentEndpoints> SegmentEndpointsOnLine(const PinholeIntrinsics& K,
                                                       const LineObservation& obs,
                                                       const Line6d& L_w) {
  if (!K.IsValid() || !IsFinite(obs) || !L_w.allFinite()) return std::nullopt;
  const double d_norm = L_w.tail<3>().norm();
  if (!(d_norm > 0)) return std::nullopt;
  const Eigen::Vector3d d = L_w.tail<3>() / d_norm;
  const Eigen::Vector3d p0 = d.cross(L_w.head<3>() / d_norm);
  const Eigen::Vector3d c = obs.T_w_c.translation();
  const Eigen::Vector3d w0 = c - p0;
  SegmentEndpoints out;
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector2d& uv = k == 0 ? obs.start : obs.end;
    // Ray c + lambda f with f = R (x, y, 1): lambda is the camera depth z of the ray point.
    const Eigen::Vector3d f = obs.T_w_c.rotation() * K.ToNormalized<double>(uv).homogeneous();
    // Closest points of the ray and the line p0 + mu d (|d| = 1): minimise
    // |w0 + lambda f - mu d|^2 -> [a -b; b -1] [lambda; mu] = [-f.w0; -d.w0].
    const double a = f.squaredNorm(), b = f.dot(d), fw = f.dot(w0), dw = d.dot(w0);
    const double denom = a - b * b;  // = |f x d|^2
    if (!(denom > 1e-12 * a)) return std::nullopt;
    const double lambda = (b * dw - fw) / denom;
    const double mu = (a * dw - b * fw) / denom;
    (k == 0 ? out.start_w : out.end_w) = p0 + mu * d;
    (k == 0 ? out.start_depth : out.end_depth) = lambda;
  }
  return out;
}

LineTriangulationResult TriangulateLineTwoView(const PinholeIntrinsics& K, const LineObservation& a,
                                               const LineObservation& b,
                                               const LineTriangulationOptions& options) {
  LineTriangulationResult result;
  const std::vector<LineObservation> obs = {a, b};
  std::vector<Eigen::Vector4d> planes;
  if (!Planes(K, obs, options, &planes, &result)) return result;
  if (!ParallaxOk(planes, options, &result)) return result;
  return Finish(K, obs, LineFromPlanes<double>(planes[0], planes[1]), options, result);
}

LineTriangulationResult TriangulateLine(const PinholeIntrinsics& K,
                                        const std::vector<LineObservation>& obs,
                                        const LineTriangulationOptions& options) {
  LineTriangulationResult result;
  if (obs.size() < 2) {
    return Fail(result, Status::kTooFewViews, std::to_string(obs.size()) + " observations");
  }
  std::vector<Eigen::Vector4d> planes;
  if (!Planes(K, obs, options, &planes, &result)) return result;
  if (!ParallaxOk(planes, options, &result)) return result;

  // Conditioning: camera centres centred at the origin with RMS distance 1. A world point
  // x = c + s x' lies on (m, e) iff m . x' + (m . c + e) / s = 0.
  const std::size_t n = obs.size();
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& o : obs) c += o.T_w_c.translation();
  c /= static_cast<double>(n);
  double s = 0.0;
  for (const auto& o : obs) s += (o.T_w_c.translation() - c).squaredNorm();
  s = std::sqrt(s / static_cast<double>(n));
  if (!(s > 1e-12 * (1.0 + c.norm()))) s = 1.0;  // one centre: parallax already checked
  Eigen::MatrixXd A(n, 4);
  for (std::size_t i = 0; i < n; ++i) {
    A.block<1, 3>(i, 0) = planes[i].head<3>().transpose();
    A(i, 3) = (planes[i].head<3>().dot(c) + planes[i](3)) / s;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  // sigma2 = 0 (all planes equal) only passes the parallax check with a zero minimum angle.
  result.sigma_ratio = n < 3 ? 0.0 : sigma(1) > 0.0 ? sigma(2) / sigma(1) : 1.0;
  if (!(result.sigma_ratio <= options.max_sigma_ratio)) {
    std::ostringstream msg;
    msg << "sigma3 / sigma2 = " << result.sigma_ratio << " > " << options.max_sigma_ratio;
    return Fail(result, Status::kIllConditioned, msg.str());
  }
  // Two homogeneous points X1, X2 of the line (normalised frame) -> Plücker:
  // d' = w1 x2 - w2 x1, n' = x1 x x2; back to the world: d = d', n = s n' + c x d'.
  const Eigen::Vector4d X1 = svd.matrixV().col(2), X2 = svd.matrixV().col(3);
  const Eigen::Vector3d d = X1(3) * X2.head<3>() - X2(3) * X1.head<3>();
  Line6d L;
  L.head<3>() = s * X1.head<3>().cross(X2.head<3>()) + c.cross(d);
  L.tail<3>() = d;
  return Finish(K, obs, L, options, result);
}

std::optional<Eigen::VectorXd> LineReprojectionErrors(const PinholeIntrinsics& K,
                                                      const std::vector<LineObservation>& obs,
                                                      const Line6d& L_w) {
  if (!K.IsValid() || !L_w.allFinite()) return std::nullopt;
  Eigen::VectorXd errors(2 * obs.size());
  for (std::size_t i = 0; i < obs.size(); ++i) {
    if (!IsFinite(obs[i])) return std::nullopt;
    const Line6d L_c = TransformLine(obs[i].T_w_c.Inverse(), L_w);
    if (LineThroughCameraCentre(L_c)) return std::nullopt;
    const auto r = EndpointLineResidual(ProjectLinePixels(K, L_c), obs[i].start, obs[i].end);
    if (!r) return std::nullopt;
    errors.segment<2>(2 * i) = *r;
  }
  return errors;
}

namespace {

// Residuals (2 per view, pixels) and, when J is non-null, their Jacobian w.r.t. the tangent of
// the orthonormal line. False when a view's image line is undefined.
bool Linearize(const PinholeIntrinsics& K, const std::vector<LineObservation>& obs,
               const std::vector<SE3d>& T_c_w, const OrthonormalLine& line, Eigen::VectorXd* r,
               Eigen::MatrixXd* J) {
  Eigen::Matrix<double, 6, 4> d_Lw_d_delta;
  const Line6d L_w = PluckerFromOrthonormal(line, J ? &d_Lw_d_delta : nullptr);
  r->resize(2 * obs.size());
  if (J) J->resize(2 * obs.size(), 4);
  for (std::size_t i = 0; i < obs.size(); ++i) {
    Matrix6d d_Lc_d_Lw;
    const Line6d L_c = TransformLine(T_c_w[i], L_w, nullptr, J ? &d_Lc_d_Lw : nullptr);
    if (LineThroughCameraCentre(L_c)) return false;
    Eigen::Matrix<double, 3, 6> d_l_d_Lc;
    const Eigen::Vector3d l = ProjectLinePixels(K, L_c, J ? &d_l_d_Lc : nullptr);
    Eigen::Matrix<double, 2, 3> d_r_d_l;
    const auto ri = EndpointLineResidual(l, obs[i].start, obs[i].end, J ? &d_r_d_l : nullptr);
    if (!ri) return false;
    r->segment<2>(2 * i) = *ri;
    if (J) J->block<2, 4>(2 * i, 0) = d_r_d_l * d_l_d_Lc * d_Lc_d_Lw * d_Lw_d_delta;
  }
  return r->allFinite() && (!J || J->allFinite());
}

}  // namespace

std::optional<LineRefinement> RefineLine(const PinholeIntrinsics& K,
                                         const std::vector<LineObservation>& obs,
                                         const Line6d& L_w_init,
                                         const LineRefinementOptions& options) {
  if (!K.IsValid() || obs.empty()) return std::nullopt;
  for (const LineObservation& o : obs) {
    if (!IsFinite(o)) return std::nullopt;
  }
  const auto start = OrthonormalFromPlucker(L_w_init);
  if (!start) return std::nullopt;
  std::vector<SE3d> T_c_w;
  for (const LineObservation& o : obs) T_c_w.push_back(o.T_w_c.Inverse());
  OrthonormalLine line = *start;
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  if (!Linearize(K, obs, T_c_w, line, &r, &J)) return std::nullopt;
  LineRefinement out;
  out.initial_cost = 0.5 * r.squaredNorm();
  double cost = out.initial_cost;
  double lambda = options.initial_lambda;
  for (int it = 0; it < options.max_iterations; ++it) {
    const Eigen::Matrix4d H = J.transpose() * J;
    const Eigen::Vector4d g = J.transpose() * r;
    Eigen::Matrix4d A = H;
    A.diagonal() += lambda * H.diagonal().cwiseMax(1e-12);
    const Eigen::Vector4d delta = A.ldlt().solve(-g);
    if (!delta.allFinite()) break;
    const OrthonormalLine candidate = line.Plus(delta);
    Eigen::VectorXd r_new;
    Eigen::MatrixXd J_new;
    const bool ok = Linearize(K, obs, T_c_w, candidate, &r_new, &J_new);
    const double cost_new = ok ? 0.5 * r_new.squaredNorm() : std::numeric_limits<double>::max();
    if (ok && cost_new <= cost) {
      const double decrease = cost - cost_new;
      line = candidate;
      r = r_new;
      J = J_new;
      cost = cost_new;
      ++out.iterations;
      lambda = std::max(lambda / 10.0, 1e-12);
      if (delta.norm() < options.parameter_tolerance ||
          decrease <= options.cost_tolerance * (cost + 1e-300)) {
        out.converged = true;
        break;
      }
    } else {
      lambda *= 10.0;
      if (lambda > 1e8) {
        out.converged = true;  // no descent direction left: at a minimum up to rounding
        break;
      }
    }
  }
  out.final_cost = cost;
  out.L_w = PluckerFromOrthonormal(line);
  return out;
}

LineTriangulationResult TriangulateLineRefined(const PinholeIntrinsics& K,
                                               const std::vector<LineObservation>& obs,
                                               const LineTriangulationOptions& options,
                                               const LineRefinementOptions& refinement) {
  const LineTriangulationResult linear = TriangulateLine(K, obs, options);
  if (!linear.ok()) return linear;
  const auto refined = RefineLine(K, obs, linear.L_w, refinement);
  if (!refined || !(refined->final_cost <= refined->initial_cost)) return linear;
  LineTriangulationResult result = linear;
  result = Finish(K, obs, refined->L_w, options, result);
  if (!result.ok()) return linear;  // the refined line fails cheirality: keep the linear one
  result.refine_iterations = refined->iterations;
  return result;
}

LineTriangulationResult TriangulateLineBestPair(const PinholeIntrinsics& K,
                                                const std::vector<LineObservation>& obs,
                                                const LineTriangulationOptions& options,
                                                std::pair<int, int>* pair) {
  LineTriangulationResult result;
  if (obs.size() < 2) {
    return Fail(result, Status::kTooFewViews, std::to_string(obs.size()) + " observations");
  }
  std::vector<Eigen::Vector4d> planes;
  if (!Planes(K, obs, options, &planes, &result)) return result;
  int best_i = 0, best_j = 1;
  double best = -1.0;
  for (std::size_t i = 0; i < planes.size(); ++i) {
    for (std::size_t j = i + 1; j < planes.size(); ++j) {
      const double angle = PlaneAngle(planes[i], planes[j]);
      if (angle > best) {
        best = angle;
        best_i = static_cast<int>(i);
        best_j = static_cast<int>(j);
      }
    }
  }
  if (pair) *pair = {best_i, best_j};
  return TriangulateLineTwoView(K, obs[best_i], obs[best_j], options);
}

}  // namespace plucker
