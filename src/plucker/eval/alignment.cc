#include "plucker/eval/alignment.h"

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
  }
  return "unknown";
}

std::optional<AlignmentMode> ParseAlignmentMode(const std::string& name) {
  if (name == "none") return AlignmentMode::kNone;
  if (name == "se3") return AlignmentMode::kSE3;
  if (name == "sim3") return AlignmentMode::kSim3;
  return std::nullopt;
}

SE3d Similarity::Apply(const SE3d& T) const {
  return SE3d(Eigen::Matrix3d(R * T.RotationMatrix()), scale * (R * T.translation()) + t);
}

std::optional<Similarity> UmeyamaAlignment(const std::vector<Eigen::Vector3d>& source,
                                           const std::vector<Eigen::Vector3d>& target,
                                           AlignmentMode mode) {
  if (source.size() != target.size() || source.empty()) return std::nullopt;
  Similarity S;
  if (mode == AlignmentMode::kNone) return S;
  const double n = static_cast<double>(source.size());
  Eigen::Vector3d mu_s = Eigen::Vector3d::Zero(), mu_t = Eigen::Vector3d::Zero();
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
  }
  S.t = mu_t - S.scale * (S.R * mu_s);
  if (!S.R.allFinite() || !S.t.allFinite() || !std::isfinite(S.scale)) return std::nullopt;
  return S;
}

std::vector<Eigen::Vector3d> Positions(const std::vector<SE3d>& poses) {
  std::vector<Eigen::Vector3d> p;
  p.reserve(poses.size());
  for (const SE3d& T : poses) p.push_back(T.translation());
  return p;
}

}  // namespace eval
}  // namespace plucker
