// Hand-made trajectories shared by the eval tests (header-only, test use only).
#pragma once

#include <cmath>
#include <vector>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/se3.h"

namespace plucker {
namespace eval {
namespace testing {

// A KITTI-like camera (1241x376 images) for the track tests.
inline PinholeIntrinsics KittiLikeCamera() {
  PinholeIntrinsics k;
  k.fx = k.fy = 700;
  k.cx = 600;
  k.cy = 180;
  return k;
}

// n poses driving straight along +z (KITTI cam0 forward) with `step` metres a frame.
inline std::vector<SE3d> StraightLine(int n, double step) {
  std::vector<SE3d> poses;
  for (int i = 0; i < n; ++i) {
    poses.emplace_back(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, step * i));
  }
  return poses;
}

// A smooth 3D curve with changing orientation (a helix-like drive), n poses.
inline std::vector<SE3d> Curve(int n) {
  std::vector<SE3d> poses;
  for (int i = 0; i < n; ++i) {
    const double s = 0.05 * i;
    const Eigen::Vector3d t(10 * std::sin(s), 0.5 * std::sin(3 * s), 10 * (1 - std::cos(s)) + s);
    const Eigen::Quaterniond q(Eigen::AngleAxisd(s, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(0.1 * std::sin(2 * s), Eigen::Vector3d::UnitX()));
    poses.emplace_back(q, t);
  }
  return poses;
}

}  // namespace testing
}  // namespace eval
}  // namespace plucker
