// The per-module lists of Jacobian checks; registry.cc assembles them.
#pragma once

#include <vector>

#include "plucker/verify/jacobian_check.h"

namespace plucker {
namespace verify {

std::vector<NamedJacobianCheck> SE3JacobianChecks();              // se3_checks.cc
std::vector<NamedJacobianCheck> LineJacobianChecks();             // line_checks.cc
std::vector<NamedJacobianCheck> ProjectionJacobianChecks();       // projection_checks.cc
std::vector<NamedJacobianCheck> CameraJacobianChecks();           // camera_checks.cc
std::vector<NamedJacobianCheck> LidarFactorJacobianChecks();      // lidar_factor_checks.cc
std::vector<NamedJacobianCheck> PointFactorJacobianChecks();      // point_factor_checks.cc
std::vector<NamedJacobianCheck> LineFactorJacobianChecks();       // line_factor_checks.cc
std::vector<NamedJacobianCheck> ImuFactorJacobianChecks();        // imu_factor_checks.cc
std::vector<NamedJacobianCheck> MarginalizationJacobianChecks();  // marginalization_checks.cc

}  // namespace verify
}  // namespace plucker
