#include "plucker/lidar/sweep_motion.h"

#include <cmath>

#include "plucker/lidar/deskew.h"

namespace plucker {
namespace lidar {

bool SweepFeatureExtractor::Extract(const LidarScan& scan, const SE3d& T_start_end,
                                    const FeatureOptions& ring_options,
                                    const GeometricFeatureOptions& options, ScanFeatures* f,
                                    std::string* error, Matrix6d* plane_information) {
  FeatureOptions o = ring_options;
  o.compute_times = true;
  deskewed_.points = scan.points;
  deskewed_.time = scan.time;
  DeskewPoints(T_start_end, ring_options.scan_period, deskewed_.time, &deskewed_.points);
  if (!extractor_.Extract(deskewed_, o, options, f, error, plane_information)) return false;
  RedistortPoints(T_start_end, o.scan_period, f->edge_times, &f->edges);
  RedistortPoints(T_start_end, o.scan_period, f->plane_times, &f->planes);
  f->sharp = f->edges;
  f->flat = f->planes;
  if (!ring_options.compute_times) f->edge_times.clear(), f->plane_times.clear();
  return true;
}

SE3d SweepFeatureExtractor::SearchForwardMotion(const LidarScan& scan,
                                                const FeatureOptions& ring_options,
                                                const GeometricFeatureOptions& options,
                                                const SweepMotionSearch& search) {
  ScanFeatures f;
  std::string error;
  Matrix6d info;
  auto motion = [](double x, double yaw) {
    return SE3d(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                Eigen::Vector3d(x, 0.0, 0.0));
  };
  // The plane information of a candidate along one tangent direction (index into (dtheta, dt)):
  // -1 when the extraction fails.
  auto information = [&](double x, double yaw, int axis) {
    if (!Extract(scan, motion(x, yaw), ring_options, options, &f, &error, &info)) return -1.0;
    return info(axis, axis);
  };
  constexpr int kYaw = 2, kForward = 3;  // rotation about z, translation along x
  double best_x = 0.0, best_yaw = 0.0;
  // Yaw by the rotation information about z at the best forward motion, then the forward motion
  // by the translation information along x at the best yaw; on the coarse grid, then on the fine
  // one around the best.
  const double max_yaw = search.max_yaw_deg * M_PI / 180.0;
  const double yaw_step = search.yaw_step_deg * M_PI / 180.0;
  // Grid sizes (a step <= 0 gives a single value: 0).
  const int yaw_steps = yaw_step > 0.0 ? static_cast<int>(std::round(max_yaw / yaw_step)) : 0;
  const int x_steps = search.coarse_step > 0.0
                          ? static_cast<int>(std::round(search.max_forward / search.coarse_step))
                          : 0;
  for (double scale : {1.0, 0.25}) {
    const double x0 = best_x, yaw0 = scale == 1.0 ? 0.0 : best_yaw;
    const int ky = scale == 1.0 ? yaw_steps : 4;
    double best = -1.0;
    for (int k = -ky; k <= ky; ++k) {
      const double yaw = yaw0 + k * scale * yaw_step;
      if (std::abs(yaw) > max_yaw + 1e-12) continue;
      const double score = information(x0, yaw, kYaw);
      if (score > best) best = score, best_yaw = yaw;
    }
    best = -1.0;
    const int kx0 = scale == 1.0 ? 0 : -4, kx1 = scale == 1.0 ? x_steps : 4;
    for (int k = kx0; k <= kx1; ++k) {
      const double x = (scale == 1.0 ? 0.0 : x0) + k * scale * search.coarse_step;
      if (x < 0.0 || x > search.max_forward + 1e-12) continue;
      const double score = information(x, best_yaw, kForward);
      if (score > best) best = score, best_x = x;
    }
  }
  return motion(best_x, best_yaw);
}

}  // namespace lidar
}  // namespace plucker
