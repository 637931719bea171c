#include "plucker/lidar/deskew.h"

#include <algorithm>

namespace plucker {
namespace lidar {

SE3d InterpolateMotion(const SE3d& T_start_end, double fraction) {
  const double a = std::clamp(fraction, 0.0, 1.5);
  const Eigen::Vector3d w = LogSO3(T_start_end.rotation());
  return SE3d(ExpSO3<double>(a * w), a * T_start_end.translation());
}

bool DeskewPoints(const SE3d& T_start_end, double period, const std::vector<double>& times,
                  std::vector<Eigen::Vector3d>* points) {
  if (times.size() != points->size() || !(period > 0.0)) return false;
  const Eigen::Vector3d w = LogSO3(T_start_end.rotation());
  const Eigen::Vector3d t = T_start_end.translation();
  for (std::size_t i = 0; i < points->size(); ++i) {
    const double a = std::clamp(times[i] / period, 0.0, 1.5);
    (*points)[i] = ExpSO3<double>(a * w) * (*points)[i] + a * t;
  }
  return true;
}

bool RedistortPoints(const SE3d& T_start_end, double period, const std::vector<double>& times,
                     std::vector<Eigen::Vector3d>* points) {
  if (times.size() != points->size() || !(period > 0.0)) return false;
  for (std::size_t i = 0; i < points->size(); ++i)
    (*points)[i] = InterpolateMotion(T_start_end, times[i] / period).Inverse() * (*points)[i];
  return true;
}

}  // namespace lidar
}  // namespace plucker
