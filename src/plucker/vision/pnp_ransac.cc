#include "plucker/vision/pnp_ransac.h"

#include <algorithm>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

namespace plucker {
namespace vision {
namespace {

int CvSolver(PnpSolver s) {
  switch (s) {
    case PnpSolver::kEpnp:
      return cv::SOLVEPNP_EPNP;
    case PnpSolver::kAp3p:
      return cv::SOLVEPNP_AP3P;
    case PnpSolver::kP3p:
      return cv::SOLVEPNP_P3P;
    case PnpSolver::kIterative:
      return cv::SOLVEPNP_ITERATIVE;
    case PnpSolver::kSqpnp:
      return cv::SOLVEPNP_SQPNP;
  }
  return cv::SOLVEPNP_EPNP;
}

std::vector<cv::Point2d> ToCv(const std::vector<Eigen::Vector2d>& x) {
  std::vector<cv::Point2d> out;
  out.reserve(x.size());
  for (const Eigen::Vector2d& p : x) out.emplace_back(p.x(), p.y());
  return out;
}

}  // namespace

PnpRansacResult PnpRansac(const std::vector<Eigen::Vector3d>& points_w,
                          const std::vector<Eigen::Vector2d>& uv, const PinholeIntrinsics& K,
                          const PnpRansacOptions& options) {
  PnpRansacResult result;
  const int n = static_cast<int>(std::min(points_w.size(), uv.size()));
  if (points_w.size() != uv.size() || n < options.min_correspondences) {
    result.status = PnpStatus::kTooFewCorrespondences;
    result.message = std::to_string(n) + " correspondences";
    return result;
  }
  std::vector<cv::Point3d> object;
  object.reserve(points_w.size());
  for (const Eigen::Vector3d& p : points_w) object.emplace_back(p.x(), p.y(), p.z());
  const std::vector<cv::Point2d> image = ToCv(uv);
  const cv::Matx33d Kcv(K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1);
  cv::Mat rvec, tvec;
  bool found = false;
  try {
    found = cv::solvePnPRansac(object, image, Kcv, cv::noArray(), rvec, tvec, false,
                               options.iterations, static_cast<float>(options.threshold_px),
                               options.confidence, result.inliers, CvSolver(options.solver));
  } catch (const cv::Exception& e) {
    result.status = PnpStatus::kError;
    result.message = e.what();
    result.inliers.clear();
    return result;
  }
  if (!found) {
    result.status = PnpStatus::kNoSolution;
    result.message = "no RANSAC model";
    return result;
  }
  if (static_cast<int>(result.inliers.size()) < options.min_inliers) {
    result.status = PnpStatus::kTooFewInliers;
    result.message = std::to_string(result.inliers.size()) + " inliers";
    return result;
  }
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d R_c_w;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R_c_w(r, c) = R(r, c);
  const Eigen::Vector3d t_c_w(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
  if (!R_c_w.allFinite() || !t_c_w.allFinite()) {
    result.status = PnpStatus::kNotFinite;
    result.message = "a non-finite pose";
    return result;
  }
  result.T_c_w = SE3d(R_c_w, t_c_w);
  if (!result.T_c_w.rotation().coeffs().allFinite()) {
    result.status = PnpStatus::kNotFinite;
    result.message = "a non-finite pose";
    return result;
  }
  result.status = PnpStatus::kOk;
  return result;
}

EssentialPoseResult EssentialPose(const std::vector<Eigen::Vector2d>& xa,
                                  const std::vector<Eigen::Vector2d>& xb,
                                  const EssentialPoseOptions& options) {
  EssentialPoseResult result;
  if (xa.size() != xb.size() || xa.size() < 5) {
    result.status = EssentialPoseStatus::kTooFewMatches;
    result.message = "too few matches (" + std::to_string(std::min(xa.size(), xb.size())) + ")";
    return result;
  }
  const std::vector<cv::Point2d> a = ToCv(xa), b = ToCv(xb);
  try {
    cv::Mat mask;
    cv::Mat E = cv::findEssentialMat(a, b, 1.0, cv::Point2d(0, 0), cv::RANSAC, options.confidence,
                                     options.threshold, mask);
    const bool several = E.rows > 3 && E.rows % 3 == 0 && E.cols == 3;
    if (several && options.take_first_of_several) E = E.rowRange(0, 3).clone();
    if (E.rows != 3 || E.cols != 3) {
      result.status = EssentialPoseStatus::kNoEssentialMatrix;
      result.message = "no essential matrix";
      return result;
    }
    cv::Mat R, t;
    result.inliers = cv::recoverPose(E, a, b, cv::Mat::eye(3, 3, CV_64F), R, t,
                                     options.max_depth_baselines, mask);
    for (int r = 0; r < 3; ++r) {
      result.t_b_a(r) = t.at<double>(r);
      for (int c = 0; c < 3; ++c) result.R_b_a(r, c) = R.at<double>(r, c);
    }
    result.inlier_mask.assign(mask.begin<unsigned char>(), mask.end<unsigned char>());
  } catch (const cv::Exception& e) {
    result.status = EssentialPoseStatus::kError;
    result.message = e.what();
    result.inliers = 0;
    result.inlier_mask.clear();
    return result;
  }
  result.status = EssentialPoseStatus::kOk;
  return result;
}

}  // namespace vision
}  // namespace plucker
