// Closed-form alignment of an estimated trajectory to the ground truth (Umeyama 1991).
//
// Finds the similarity S = (s, R, t) minimising sum_i |p_gt_i - (s R p_est_i + t)|^2:
//   mu_e, mu_g  the centroids;  sigma_e^2 = mean |p_est_i - mu_e|^2;
//   C = mean (p_gt_i - mu_g)(p_est_i - mu_e)^T = U D V^T (SVD);
//   W = diag(1, 1, det(U) det(V))   (flips the weakest axis when the best orthogonal map would
//                                    be a reflection);
//   R = U W V^T,  s = trace(D W) / sigma_e^2 (Sim(3); 1 for SE(3)),  t = mu_g - s R mu_e.
// Applied to a pose: T_gt_frame ~ S * T_est_frame, i.e. R' = R R_est, t' = s R t_est + t.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "plucker/geometry/se3.h"

namespace plucker {
namespace eval {

// kPositionYaw: translation and a rotation about the world z axis only (4 degrees of freedom),
// what visual-inertial odometry can observe in a gravity-aligned (z up) world:
//   yaw = atan2(sum (e_x g_y - e_y g_x), sum (e_x g_x + e_y g_y)) over the centred positions e
//   (estimate) and g (ground truth), t = mu_g - Rz(yaw) mu_e. When the positions have no
//   horizontal extent, the yaw that best agrees with the orientations is used instead.
enum class AlignmentMode { kNone, kSE3, kSim3, kPositionYaw };

std::string AlignmentName(AlignmentMode mode);  // "none", "se3", "sim3", "posyaw"
std::optional<AlignmentMode> ParseAlignmentMode(const std::string& name);

// p_target = scale * R * p_source + t.
struct Similarity {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double scale = 1.0;

  Eigen::Vector3d operator*(const Eigen::Vector3d& p) const { return scale * (R * p) + t; }
  SE3d Apply(const SE3d& T) const;  // (R R_T, s R t_T + t)
};

// Umeyama's alignment of `source` onto `target` (same sizes). kNone returns the identity.
// Returns std::nullopt when the sizes differ, are zero, or (kSim3) when the source points all
// coincide so that the scale is undefined. Collinear points (a straight drive) are accepted: the
// rotation about that line is then not unique but any choice gives the same minimal residual.
std::optional<Similarity> UmeyamaAlignment(const std::vector<Eigen::Vector3d>& source,
                                           const std::vector<Eigen::Vector3d>& target,
                                           AlignmentMode mode);

// Aligns an estimated trajectory to the ground truth: Umeyama on the positions, except that for
// (nearly) collinear positions -- a straight drive, where the second singular value of C is below
// `kCollinearRatio` times the first -- the positions do not fix the rotation about the line (roll),
// and noise would pick it arbitrarily (tens of degrees of fake rotation error). There the roll
// about the estimate's principal direction u is chosen to best agree with the orientations:
//   R' = R Rot(u, phi),  phi = argmax sum_i trace(R_gt_i^T R' R_est_i) = atan2(b, a),
//   M = sum_i R_est_i R_gt_i^T R,  a = trace(M) - u^T M u,  b = trace(M [u]x),
// which leaves the fit along the line, and hence the positional error, (nearly) unchanged.
struct TrajectoryAlignment {
  Similarity S;                         // est -> gt
  bool roll_from_orientations = false;  // the collinear case above was used
};
constexpr double kCollinearRatio = 1e-2;
std::optional<TrajectoryAlignment> AlignTrajectory(const std::vector<SE3d>& est,
                                                   const std::vector<SE3d>& gt, AlignmentMode mode);

std::vector<Eigen::Vector3d> Positions(const std::vector<SE3d>& poses);

}  // namespace eval
}  // namespace plucker
