// A random IMU factor configuration (preintegrated readings and the states at both ends), shared
// by the Jacobian checks (imu_factor_checks.cc, which documents the curated cases 0-5) and the
// factor benchmark.
#pragma once

#include <Eigen/Core>

#include "plucker/factors/imu_preintegration.h"
#include "plucker/geometry/se3.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace verify {

const Eigen::Vector3d kImuSampleGravity(0.0, 0.0, -9.81);

struct ImuFactorSample {
  ImuPreintegration preintegration{sensor::ImuBias(), sensor::ImuModel()};
  SE3d T_w_b_i, T_w_b_j;
  Eigen::Vector3d v_i, v_j;
  Eigen::Matrix<double, 6, 1> bias_i, bias_j;  // [b_g, b_a]
};

// Curated configuration `i` (0-5), or a random one for i >= 6.
ImuFactorSample MakeImuFactorSample(Rng& rng, int i);

}  // namespace verify
}  // namespace plucker
