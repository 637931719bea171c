// Seeded random configurations for Jacobian checks and tests.
#pragma once

#include <Eigen/Core>
#include <random>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/se3.h"

namespace plucker {
namespace verify {

using Rng = std::mt19937_64;

inline double Uniform(Rng& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}
inline Eigen::Vector3d RandomVector(Rng& rng, double scale = 1.0) {
  return Eigen::Vector3d(Uniform(rng, -scale, scale), Uniform(rng, -scale, scale),
                         Uniform(rng, -scale, scale));
}
inline Eigen::Vector3d RandomUnitVector(Rng& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Vector3d v(n(rng), n(rng), n(rng));
  while (v.norm() < 1e-6) v = Eigen::Vector3d(n(rng), n(rng), n(rng));
  return v.normalized();
}
// Uniformly distributed rotation.
inline Eigen::Quaterniond RandomRotation(Rng& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized();
}
inline SE3d RandomPose(Rng& rng, double translation_scale = 2.0) {
  return SE3d(RandomRotation(rng), RandomVector(rng, translation_scale));
}
// A rotation of angle in [pi - eps, pi] about a random axis.
inline Eigen::Quaterniond RotationNearPi(Rng& rng, double eps = 1e-6) {
  const double angle = M_PI - Uniform(rng, 0.0, eps);
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, RandomUnitVector(rng)));
}

// Sample i of a pose sequence: the curated hard cases first (identity, a rotation of exactly pi,
// one within 1e-7 of pi, a 1e-9 rad rotation), then uniformly random poses.
inline SE3d SamplePose(Rng& rng, int i) {
  switch (i) {
    case 0:
      return SE3d();
    case 1:
      return SE3d(RotationNearPi(rng, 0.0), RandomVector(rng));
    case 2:
      return SE3d(RotationNearPi(rng, 1e-7), RandomVector(rng));
    case 3:
      return SE3d(ExpSO3<double>(RandomUnitVector(rng) * 1e-9), RandomVector(rng));
    default:
      return RandomPose(rng);
  }
}

// Intrinsics of a VGA-like camera, focal length 300-900 px, aspect within 5 %.
inline PinholeIntrinsics SampleIntrinsics(Rng& rng) {
  PinholeIntrinsics K;
  K.fx = Uniform(rng, 300, 900);
  K.fy = K.fx * Uniform(rng, 0.95, 1.05);
  K.cx = Uniform(rng, 200, 700);
  K.cy = Uniform(rng, 150, 400);
  return K;
}

}  // namespace verify
}  // namespace plucker
