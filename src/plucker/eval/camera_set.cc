#include "plucker/eval/camera_set.h"

#include <algorithm>
#include <cmath>

#include <Eigen/SVD>

#include "plucker/geometry/median.h"

namespace plucker {
namespace eval {
CameraSetErrors CompareCameraSets(const std::vector<std::optional<SE3d>>& est,
                                  const std::vector<SE3d>& gt, AlignmentMode mode) {
  CameraSetErrors out;
  out.cameras = static_cast<int>(gt.size());
  if (est.size() != gt.size()) {
    out.message = "the estimate has " + std::to_string(est.size()) + " cameras, the ground truth " +
                  std::to_string(gt.size());
    return out;
  }
  std::vector<SE3d> e, g;
  for (std::size_t i = 0; i < est.size(); ++i) {
    if (!est[i]) {
      out.missing.push_back(static_cast<int>(i));
      continue;
    }
    e.push_back(*est[i]);
    g.push_back(gt[i]);
  }
  out.registered = static_cast<int>(e.size());
  if (e.size() < 3) {
    out.message = "needs at least 3 registered cameras, has " + std::to_string(e.size());
    return out;
  }
  const std::optional<Similarity> S = UmeyamaAlignment(Positions(e), Positions(g), mode);
  if (!S) {
    out.message = "the alignment is undefined (camera centres coincide)";
    return out;
  }
  out.scale = S->scale;
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < e.size(); ++i)
    M += g[i].RotationMatrix() * e[i].RotationMatrix().transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d W = Eigen::Matrix3d::Identity();
  W(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  const Eigen::Quaterniond R_o(Eigen::Matrix3d(svd.matrixU() * W * svd.matrixV().transpose()));
  constexpr double kDeg = 180.0 / M_PI;
  for (std::size_t i = 0; i < e.size(); ++i) {
    const SE3d a = S->Apply(e[i]);
    out.centre_error.push_back((a.translation() - g[i].translation()).norm());
    out.rotation_error_centres_deg.push_back(a.rotation().angularDistance(g[i].rotation()) * kDeg);
    out.rotation_error_deg.push_back((R_o * e[i].rotation()).angularDistance(g[i].rotation()) *
                                     kDeg);
  }
  out.median_rotation_centres_deg = MidpointMedian(out.rotation_error_centres_deg);
  out.max_rotation_centres_deg = *std::max_element(out.rotation_error_centres_deg.begin(),
                                                   out.rotation_error_centres_deg.end());
  out.median_centre = MidpointMedian(out.centre_error);
  out.max_centre = *std::max_element(out.centre_error.begin(), out.centre_error.end());
  out.median_rotation_deg = MidpointMedian(out.rotation_error_deg);
  out.max_rotation_deg =
      *std::max_element(out.rotation_error_deg.begin(), out.rotation_error_deg.end());
  out.ok = true;
  return out;
}

}  // namespace eval
}  // namespace plucker
