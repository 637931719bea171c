// The convention of Strecha's `.camera` files (io/camera_calibration.h: T_w_c = [R | C]) checked
// on the real photographs: ORB matches between two neighbouring views of fountain-P11 fit the
// epipolar geometry of the ground-truth poses read that way, lie in front of both cameras, and
// do not fit the transposed reading (R as world-to-camera).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>

#include "plucker/geometry/se3.h"
#include "plucker/geometry/so3.h"
#include "plucker/io/camera_calibration.h"
#include "plucker/io/image_folder.h"

namespace plucker {
namespace vision {
namespace {

namespace fs = std::filesystem;

constexpr int kReduction = 4;  // images decoded at 768x512 (cheap under the sanitizers)

// K of the reduced image: pixel centres map as u' = (u + 0.5) / r - 0.5.
Eigen::Matrix3d ReducedK(const PinholeIntrinsics& K) {
  PinholeIntrinsics k;
  k.fx = K.fx / kReduction;
  k.fy = K.fy / kReduction;
  k.cx = (K.cx + 0.5) / kReduction - 0.5;
  k.cy = (K.cy + 0.5) / kReduction - 0.5;
  return k.K();
}

// Sampson distance [px] of a match under the fundamental matrix F (x2^T F x1 = 0).
double Sampson(const Eigen::Matrix3d& F, const Eigen::Vector2d& p1, const Eigen::Vector2d& p2) {
  const Eigen::Vector3d x1 = p1.homogeneous(), x2 = p2.homogeneous();
  const Eigen::Vector3d Fx1 = F * x1, Ftx2 = F.transpose() * x2;
  const double e = x2.dot(Fx1);
  return std::abs(e) / std::sqrt(Fx1.head<2>().squaredNorm() + Ftx2.head<2>().squaredNorm());
}

struct Fit {
  double median_px = 0;     // median Sampson distance
  double inlier_share = 0;  // share within 1 px
  double in_front = 0;      // share of inliers triangulated in front of both cameras
};

Fit FitPoses(const SE3d& T_w_c1, const SE3d& T_w_c2, const Eigen::Matrix3d& K,
             const std::vector<Eigen::Vector2d>& p1, const std::vector<Eigen::Vector2d>& p2) {
  const SE3d T_c2_c1 = T_w_c2.Inverse() * T_w_c1;
  const Eigen::Matrix3d E = Hat(T_c2_c1.translation()) * T_c2_c1.RotationMatrix();
  const Eigen::Matrix3d F = K.inverse().transpose() * E * K.inverse();
  std::vector<double> d;
  int inliers = 0, in_front = 0;
  for (std::size_t i = 0; i < p1.size(); ++i) {
    d.push_back(Sampson(F, p1[i], p2[i]));
    if (d.back() > 1.0) continue;
    ++inliers;
    // Midpoint triangulation of the two rays in camera 1.
    const Eigen::Vector3d r1 = K.inverse() * p1[i].homogeneous();
    const Eigen::Vector3d r2 =
        T_c2_c1.RotationMatrix().transpose() * (K.inverse() * p2[i].homogeneous());
    const Eigen::Vector3d c2 = T_c2_c1.Inverse().translation();
    Eigen::Matrix2d A;
    A << r1.dot(r1), -r1.dot(r2), r1.dot(r2), -r2.dot(r2);
    const Eigen::Vector2d depth = A.inverse() * Eigen::Vector2d(r1.dot(c2), r2.dot(c2));
    if (depth(0) > 0 && depth(1) > 0) ++in_front;
  }
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  Fit fit;
  fit.median_px = d[d.size() / 2];
  fit.inlier_share = static_cast<double>(inliers) / p1.size();
  fit.in_front = inliers > 0 ? static_cast<double>(in_front) / inliers : 0.0;
  return fit;
}

TEST(StrechaPoses, CameraFilesFitTheImages) {
  const fs::path data = fs::path(PLUCKER_SHARED_DATA_DIR) / "strecha-fountain-p11";
  if (!fs::exists(data / "cameras/0005.jpg.camera")) GTEST_SKIP() << "shared data absent: " << data;
  const io::StrechaCamera cam1 = io::ReadStrechaCamera((data / "cameras/0004.jpg.camera").string());
  const io::StrechaCamera cam2 = io::ReadStrechaCamera((data / "cameras/0005.jpg.camera").string());
  const cv::Mat image1 = io::ReadGrayImage((data / "images/0004.jpg").string(), kReduction);
  const cv::Mat image2 = io::ReadGrayImage((data / "images/0005.jpg").string(), kReduction);
  ASSERT_EQ(image1.cols, 768);

  const cv::Ptr<cv::ORB> orb = cv::ORB::create(3000);
  std::vector<cv::KeyPoint> k1, k2;
  cv::Mat d1, d2;
  orb->detectAndCompute(image1, cv::noArray(), k1, d1);
  orb->detectAndCompute(image2, cv::noArray(), k2, d2);
  cv::BFMatcher matcher(cv::NORM_HAMMING, /*crossCheck=*/true);
  std::vector<cv::DMatch> matches;
  matcher.match(d1, d2, matches);
  std::vector<Eigen::Vector2d> p1, p2;
  for (const cv::DMatch& m : matches) {
    if (m.distance > 40) continue;
    p1.emplace_back(k1[m.queryIdx].pt.x, k1[m.queryIdx].pt.y);
    p2.emplace_back(k2[m.trainIdx].pt.x, k2[m.trainIdx].pt.y);
  }
  ASSERT_GT(p1.size(), 300u);

  const Eigen::Matrix3d K = ReducedK(cam1.camera.K);
  const Fit as_documented = FitPoses(cam1.T_w_c, cam2.T_w_c, K, p1, p2);
  // The other readings: R as world-to-camera (transposed), and -C as the translation.
  auto transposed = [](const SE3d& T) {
    return SE3d(Eigen::Matrix3d(T.RotationMatrix().transpose()), T.translation());
  };
  auto negated = [](const SE3d& T) { return SE3d(T.RotationMatrix(), -T.translation()); };
  const Fit as_transposed = FitPoses(transposed(cam1.T_w_c), transposed(cam2.T_w_c), K, p1, p2);
  const Fit as_negated = FitPoses(negated(cam1.T_w_c), negated(cam2.T_w_c), K, p1, p2);
  std::printf(
      "%zu ORB matches 0004-0005; Sampson distance median / share within 1 px / inliers in "
      "front: documented %.3f px / %.3f / %.3f, R transposed %.1f px / %.3f, -C: in front %.3f\n",
      p1.size(), as_documented.median_px, as_documented.inlier_share, as_documented.in_front,
      as_transposed.median_px, as_transposed.inlier_share, as_negated.in_front);
  EXPECT_LT(as_documented.median_px, 0.5) << p1.size() << " matches";
  EXPECT_GT(as_documented.inlier_share, 0.6);
  EXPECT_GT(as_documented.in_front, 0.99);
  EXPECT_GT(as_transposed.median_px, 3.0);
  EXPECT_LT(as_transposed.inlier_share, 0.3);
  EXPECT_LT(as_negated.in_front, 0.01);  // same epipolar lines, points behind the cameras
}

}  // namespace
}  // namespace vision
}  // namespace plucker
