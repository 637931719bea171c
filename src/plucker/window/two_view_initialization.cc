#include "plucker/window/two_view_initialization.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <utility>

#include "plucker/geometry/median.h"
#include "plucker/vision/pnp_ransac.h"

namespace plucker {
namespace window {
namespace {

// Pixel distance between b's observation and a's ray rotated into b, per match (infinite for a
// ray that turns behind b).
std::vector<double> RotatedResiduals(const PinholeIntrinsics& K, const Eigen::Matrix3d& R_b_a,
                                     const std::vector<Eigen::Vector3d>& fa,
                                     const std::vector<Eigen::Vector2d>& pb) {
  std::vector<double> r(fa.size(), std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < fa.size(); ++i) {
    const Eigen::Vector3d ray = R_b_a * fa[i];
    if (ray.z() <= 1e-9) continue;
    const Eigen::Vector2d uv(K.fx * ray.x() / ray.z() + K.cx, K.fy * ray.y() / ray.z() + K.cy);
    r[i] = (uv - pb[i]).norm();
  }
  return r;
}

// The rotation that best maps the bearings fa onto fb (least squares on the unit sphere), over
// the matches with use[i].
Eigen::Matrix3d BestRotation(const std::vector<Eigen::Vector3d>& fa,
                             const std::vector<Eigen::Vector3d>& fb, const std::vector<bool>& use) {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < fa.size(); ++i)
    if (use[i]) H += fb[i].normalized() * fa[i].normalized().transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

// The median parallax left after the best pure rotation: fitted to all matches, then refitted to
// the half it explains best (so that a rotation absorbs as much of the flow as it can).
double TranslationParallax(const PinholeIntrinsics& K, const std::vector<Eigen::Vector3d>& fa,
                           const std::vector<Eigen::Vector3d>& fb,
                           const std::vector<Eigen::Vector2d>& pb) {
  std::vector<bool> use(fa.size(), true);
  Eigen::Matrix3d R = BestRotation(fa, fb, use);
  std::vector<double> r = RotatedResiduals(K, R, fa, pb);
  const double median = UpperMedian(r);
  for (std::size_t i = 0; i < r.size(); ++i) use[i] = r[i] <= median;
  R = BestRotation(fa, fb, use);
  return UpperMedian(RotatedResiduals(K, R, fa, pb));
}

}  // namespace

TwoViewResult InitializeTwoView(const PinholeIntrinsics& K,
                                const std::vector<sensor::PointObservation>& a,
                                const std::vector<sensor::PointObservation>& b,
                                const TwoViewOptions& options,
                                const std::optional<Eigen::Matrix3d>& R_b_a_known) {
  TwoViewResult result;
  std::unordered_map<int, Eigen::Vector2d> uv_a;
  for (const auto& p : a)
    if (p.point_id >= 0 && p.uv.allFinite()) uv_a[p.point_id] = p.uv;
  std::vector<Eigen::Vector2d> xa, xb;  // normalised coordinates
  std::vector<Eigen::Vector2d> pa, pb;
  for (const auto& p : b) {
    const auto it = uv_a.find(p.point_id);
    if (p.point_id < 0 || it == uv_a.end() || !p.uv.allFinite()) continue;
    xa.emplace_back((it->second.x() - K.cx) / K.fx, (it->second.y() - K.cy) / K.fy);
    xb.emplace_back((p.uv.x() - K.cx) / K.fx, (p.uv.y() - K.cy) / K.fy);
    pa.push_back(it->second);
    pb.push_back(p.uv);
  }
  result.common_tracks = static_cast<int>(xa.size());
  if (result.common_tracks < std::max(options.min_common_tracks, 5)) {
    result.message = "too few common point tracks (" + std::to_string(result.common_tracks) + ")";
    return result;
  }
  vision::EssentialPoseOptions eo;
  eo.threshold = options.ransac_threshold_px / (0.5 * (K.fx + K.fy));
  eo.confidence = 0.999;
  eo.take_first_of_several = false;
  eo.max_depth_baselines = options.max_depth_baselines;
  const vision::EssentialPoseResult e = vision::EssentialPose(xa, xb, eo);
  if (!e.ok()) {
    result.message = e.message;
    return result;
  }
  result.inliers = e.inliers;
  if (result.inliers < options.min_inliers ||
      result.inliers < options.min_inlier_ratio * result.common_tracks) {
    result.message = "too few inliers (" + std::to_string(result.inliers) + " of " +
                     std::to_string(result.common_tracks) + ")";
    return result;
  }
  const Eigen::Matrix3d& R_b_a = e.R_b_a;
  const Eigen::Vector3d& t_b_a = e.t_b_a;
  if (R_b_a_known) {
    const Eigen::AngleAxisd diff(Eigen::Matrix3d(R_b_a_known->transpose() * R_b_a));
    result.rotation_disagreement_deg = std::abs(diff.angle()) * 180.0 / M_PI;
    if (!(result.rotation_disagreement_deg <= options.max_rotation_disagreement_deg)) {
      result.message = "the rotation disagrees with the known one by " +
                       std::to_string(result.rotation_disagreement_deg) + " deg";
      return result;
    }
  }
  // Rotation-compensated parallax of the inliers, their triangulation angles.
  std::vector<Eigen::Vector3d> fa, fb;
  std::vector<Eigen::Vector2d> pb_in;
  std::vector<double> parallax, angle;
  for (std::size_t i = 0; i < xa.size(); ++i) {
    if (!e.inlier_mask[i]) continue;
    fa.push_back(xa[i].homogeneous());
    fb.push_back(xb[i].homogeneous());
    pb_in.push_back(pb[i]);
    const Eigen::Vector3d ray = R_b_a * fa.back();
    if (ray.z() <= 1e-9) continue;
    const Eigen::Vector2d uv(K.fx * ray.x() / ray.z() + K.cx, K.fy * ray.y() / ray.z() + K.cy);
    parallax.push_back((uv - pb[i]).norm());
    angle.push_back(std::acos(std::clamp(ray.normalized().dot(fb.back().normalized()), -1.0, 1.0)) *
                    180.0 / M_PI);
  }
  if (parallax.empty()) {
    result.message = "no inlier in front of both cameras";
    return result;
  }
  result.parallax_px = UpperMedian(std::move(parallax));
  result.triangulation_angle_deg = UpperMedian(std::move(angle));
  result.translation_parallax_px = TranslationParallax(K, fa, fb, pb_in);
  if (result.parallax_px < options.min_parallax_px) {
    result.message = "too little parallax (" + std::to_string(result.parallax_px) + " px)";
    return result;
  }
  if (result.translation_parallax_px < options.min_translation_parallax_px) {
    result.message = "no translation seen: " + std::to_string(result.translation_parallax_px) +
                     " px of parallax after the best pure rotation";
    return result;
  }
  if (result.triangulation_angle_deg < options.min_triangulation_angle_deg) {
    result.message = "triangulation angle too small (" +
                     std::to_string(result.triangulation_angle_deg) + " deg)";
    return result;
  }
  if (!R_b_a.allFinite() || !t_b_a.allFinite() || t_b_a.norm() < 0.5) {
    result.message = "degenerate pose";
    return result;
  }
  result.T_b_a = SE3d(R_b_a, t_b_a.normalized());
  result.ok = true;
  return result;
}

}  // namespace window
}  // namespace plucker
