// Motion compensation (deskew) of one sweep with a constant-velocity model: a point p seen at
// time t (seconds from the scan start) goes to the scan-start frame (that of T_w_s) as
//   p_start = T_start_t * p,  T_start_t = (Exp(a * Log(R)), a * t_motion),  a = t / period,
// with (R, t_motion) = T_start_end the motion over one period (SO(3) x R(3) interpolation; it
// matches the SE(3) geodesic to first order for the small motions of one sweep).
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

// The inverse of DeskewPoints: points in the scan-start frame back to the frame of their time.
bool RedistortPoints(const SE3d& T_start_end, double period, const std::vector<double>& times,
                     std::vector<Eigen::Vector3d>* points);

}  // namespace lidar
}  // namespace plucker
