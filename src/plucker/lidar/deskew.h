// Motion compensation (deskew) of the points of one sweep with a constant-velocity model.
//
// A point p observed at time t in [0, period] (seconds from the scan start) is expressed in the
// sensor frame at the scan start (the frame of the scan pose T_w_s):
//   p_start = T_start_t * p,  T_start_t = (Exp(a * Log(R)), a * t_motion),  a = t / period,
// where (R, t_motion) = T_start_end is the motion over one period (the constant-velocity
// prediction T_{k-1}^-1 T_k). This is the SO(3) x R(3) interpolation of the project's pose
// convention; for the small motions of one sweep it matches the SE(3) geodesic to first order.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "plucker/geometry/se3.h"

namespace plucker {
namespace lidar {

// The interpolated pose T_start_t for a = t / period (clamped to [0, 1.5]).
SE3d InterpolateMotion(const SE3d& T_start_end, double fraction);

// Deskews `points` in place; `times` (seconds from the scan start) has the same size. Returns
// false (points untouched) when the sizes differ or period <= 0.
bool DeskewPoints(const SE3d& T_start_end, double period, const std::vector<double>& times,
                  std::vector<Eigen::Vector3d>* points);

}  // namespace lidar
}  // namespace plucker
