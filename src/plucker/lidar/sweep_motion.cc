#include "plucker/lidar/sweep_motion.h"

#include <cmath>

#include "plucker/lidar/deskew.h"

namespace plucker {
namespace lidar {

bool SweepFeatureExtractor::Extract(const LidarScan& scan, const SE3d& T_start_end,
                                    const FeatureOptions& ring_options,
                                    const GeometricFeatureOptions& options, ScanFeatures* f,
                                    std::string* error) {
  FeatureOptions o = ring_options;
  o.compute_times = true;
  deskewed_.points = scan.points;
  deskewed_.time = scan.time;
  DeskewPoints(T_start_end, ring_options.scan_period, deskewed_.time, &deskewed_.points);
  if (!extractor_.Extract(deskewed_, o, options, f, error)) return false;
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
  auto motion = [](double x, double yaw) {
    return SE3d(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                Eigen::Vector3d(x, 0.0, 0.0));
  };
  double best_x = 0.0, best_yaw = 0.0;
  std::size_t best_planes = 0;
  auto score = [&](double x, double yaw) {
    if (!Extract(scan, motion(x, yaw), ring_options, options, &f, &error)) return;
    if (f.planes.size() > best_planes) best_planes = f.planes.size(), best_x = x, best_yaw = yaw;
  };
  // Coordinate descent: yaw at the best forward motion, then forward motion at the best yaw,
  // on the coarse grid, then on the fine one around the best.
  const double max_yaw = search.max_yaw_deg * M_PI / 180.0;
  const double yaw_step = search.yaw_step_deg * M_PI / 180.0;
  for (double scale : {1.0, 0.25}) {
    const double x0 = best_x, yaw0 = best_yaw;
    for (int k = -4; k <= 4; ++k) {
      const double yaw = scale == 1.0 ? k * max_yaw / 4.0 : yaw0 + k * scale * yaw_step;
      if (std::abs(yaw) <= max_yaw + 1e-12) score(best_x, yaw);
    }
    for (int k = -6; k <= 6; ++k) {
      const double x =
          scale == 1.0 ? (k + 6) * search.max_forward / 12.0 : x0 + k * scale * search.coarse_step;
      if (x >= 0.0 && x <= search.max_forward + 1e-12) score(x, best_yaw);
    }
  }
  return motion(best_x, best_yaw);
}

}  // namespace lidar
}  // namespace plucker
