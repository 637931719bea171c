#include "plucker/eval/alignment.h"

#include <cmath>

#include <Eigen/SVD>

namespace plucker {
namespace eval {

std::string AlignmentName(AlignmentMode mode) {
  switch (mode) {
    case AlignmentMode::kNone:
      return "none";
    case AlignmentMode::kSE3:
      return "se3";
    case AlignmentMode::kSim3:
      return "sim3";
    case AlignmentMode::kPositionYaw:
      return "posyaw";
  }
  return "unknown";
}

std::optional<AlignmentMode> ParseAlignmentMode(const std::string& name) {
  if (name == "none") return AlignmentMode::kNone;
  if (name == "se3") return AlignmentMode::kSE3;
  if (name == "sim3") return AlignmentMode::kSim3;
  if (name == "posyaw") return AlignmentMode::kPositionYaw;
  return std::nullopt;
}

SE3d Similarity::Apply(const SE3d& T) const {
  return SE3d(Eigen::Matrix3d(R * T.RotationMatrix()), scale * (R * T.translation()) + t);
}

namespace {

struct UmeyamaDetails {
  Similarity S;
  Eigen::Vector3d singular_values = Eigen::Vector3d::Zero();    // of C, descending
  Eigen::Vector3d source_direction = Eigen::Vector3d::UnitX();  // V.col(0)
  Eigen::Vector3d mu_source = Eigen::Vector3d::Zero(), mu_target = Eigen::Vector3d::Zero();
};

std::optional<UmeyamaDetails> Umeyama(const std::vector<Eigen::Vector3d>& source,
                                      const std::vector<Eigen::Vector3d>& target,
                                      AlignmentMode mode) {
  if (source.size() != target.size() || source.empty()) return std::nullopt;
  UmeyamaDetails d;
  Similarity& S = d.S;
  if (mode == AlignmentMode::kNone) return d;
  const double n = static_cast<double>(source.size());
  Eigen::Vector3d& mu_s = d.mu_source;
  Eigen::Vector3d& mu_t = d.mu_target;
  for (std::size_t i = 0; i < source.size(); ++i) {
    mu_s += source[i];
    mu_t += target[i];
  }
  mu_s /= n;
  mu_t /= n;
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  double sigma_s = 0.0;
  for (std::size_t i = 0; i < source.size(); ++i) {
    const Eigen::Vector3d ds = source[i] - mu_s;
    C += (target[i] - mu_t) * ds.transpose();
    sigma_s += ds.squaredNorm();
  }
  C /= n;
  sigma_s /= n;
  if (mode == AlignmentMode::kSim3 && !(sigma_s > 1e-18)) return std::nullopt;
  if (C.cwiseAbs().maxCoeff() > 0.0) {
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(C, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::Matrix3d& U = svd.matrixU();
    const Eigen::Matrix3d& V = svd.matrixV();
    Eigen::Vector3d w(1.0, 1.0, 1.0);
    if (U.determinant() * V.determinant() < 0.0) w(2) = -1.0;  // singular values are descending
    S.R = U * w.asDiagonal() * V.transpose();
    if (mode == AlignmentMode::kSim3) S.scale = svd.singularValues().dot(w) / sigma_s;
    d.singular_values = svd.singularValues();
    d.source_direction = V.col(0);
  }
  S.t = mu_t - S.scale * (S.R * mu_s);
  if (!S.R.allFinite() || !S.t.allFinite() || !std::isfinite(S.scale)) return std::nullopt;
  return d;
}

}  // namespace

namespace {

Eigen::Matrix3d RotationZ(double yaw) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// Position + yaw (see the header). Nullopt for empty or different sizes.
std::optional<Similarity> PositionYaw(const std::vector<SE3d>& est, const std::vector<SE3d>& gt) {
  if (est.empty() || est.size() != gt.size()) return std::nullopt;
  Eigen::Vector3d mu_e = Eigen::Vector3d::Zero(), mu_g = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < est.size(); ++i) {
    mu_e += est[i].translation() / static_cast<double>(est.size());
    mu_g += gt[i].translation() / static_cast<double>(gt.size());
  }
  double a = 0.0, b = 0.0, spread = 0.0;
  for (std::size_t i = 0; i < est.size(); ++i) {
    const Eigen::Vector3d e = est[i].translation() - mu_e, g = gt[i].translation() - mu_g;
    a += e.x() * g.x() + e.y() * g.y();
    b += e.x() * g.y() - e.y() * g.x();
    spread += e.head<2>().squaredNorm();
  }
  if (!(spread > 1e-12 * static_cast<double>(est.size()))) {
    // No horizontal extent: the yaw that best agrees with the orientations.
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    for (std::size_t i = 0; i < est.size(); ++i)
      A += est[i].RotationMatrix() * gt[i].RotationMatrix().transpose();
    a = A(0, 0) + A(1, 1);
    b = A(0, 1) - A(1, 0);
  }
  Similarity S;
  S.R = RotationZ(std::atan2(b, a));
  S.t = mu_g - S.R * mu_e;
  return S;
}

}  // namespace

std::optional<Similarity> UmeyamaAlignment(const std::vector<Eigen::Vector3d>& source,
                                           const std::vector<Eigen::Vector3d>& target,
                                           AlignmentMode mode) {
  if (mode == AlignmentMode::kPositionYaw) {
    std::vector<SE3d> e, g;
    for (const Eigen::Vector3d& p : source) e.emplace_back(Eigen::Quaterniond::Identity(), p);
    for (const Eigen::Vector3d& p : target) g.emplace_back(Eigen::Quaterniond::Identity(), p);
    return PositionYaw(e, g);
  }
  const std::optional<UmeyamaDetails> d = Umeyama(source, target, mode);
  if (!d) return std::nullopt;
  return d->S;
}

std::optional<TrajectoryAlignment> AlignTrajectory(const std::vector<SE3d>& est,
                                                   const std::vector<SE3d>& gt,
                                                   AlignmentMode mode) {
  if (mode == AlignmentMode::kPositionYaw) {
    const std::optional<Similarity> S = PositionYaw(est, gt);
    if (!S) return std::nullopt;
    return TrajectoryAlignment{*S, false};
  }
  const std::optional<UmeyamaDetails> d = Umeyama(Positions(est), Positions(gt), mode);
  if (!d) return std::nullopt;
  TrajectoryAlignment a;
  a.S = d->S;
  if (mode == AlignmentMode::kNone) return a;
  const Eigen::Vector3d& sv = d->singular_values;
  if (!(sv(1) < kCollinearRatio * sv(0))) return a;
  // Roll about the estimate's line direction u from the orientations (see the header).
  const Eigen::Vector3d u = d->source_direction.normalized();
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < est.size(); ++i) {
    M += est[i].RotationMatrix() * gt[i].RotationMatrix().transpose();
  }
  M = M * a.S.R;
  const double a_cos = M.trace() - u.dot(M * u);
  const double b_sin = (M * Hat<double>(u)).trace();
  const double phi = std::atan2(b_sin, a_cos);
  a.S.R = a.S.R * Eigen::AngleAxisd(phi, u).toRotationMatrix();
  a.S.t = d->mu_target - a.S.scale * (a.S.R * d->mu_source);
  a.roll_from_orientations = true;
  return a;
}

std::vector<Eigen::Vector3d> Positions(const std::vector<SE3d>& poses) {
  std::vector<Eigen::Vector3d> p;
  p.reserve(poses.size());
  for (const SE3d& T : poses) p.push_back(T.translation());
  return p;
}

}  // namespace eval
}  // namespace plucker
