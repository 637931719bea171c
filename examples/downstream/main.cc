// Uses the installed library: composes two poses, checks a manifold round trip, and finds the
// ring of a LiDAR return with a sensor model.
#include <cmath>
#include <cstdio>

#include <plucker/factors/pose_manifold.h>
#include <plucker/geometry/se3.h>
#include <plucker/sensor/lidar_model.h>

int main() {
  const plucker::SE3d T_w_a(Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ())),
                            Eigen::Vector3d(1, 0, 0));
  const plucker::SE3d T_a_b(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 2, 0));
  const plucker::SE3d T_w_b = T_w_a * T_a_b;
  plucker::PoseManifold manifold;
  double x[7], y[7], d[6];
  T_w_a.ToParameters(x);
  T_w_b.ToParameters(y);
  manifold.Minus(y, x, d);
  double y2[7];
  manifold.Plus(x, d, y2);
  double err = 0;
  for (int i = 0; i < 7; ++i) err += (y2[i] - y[i]) * (y2[i] - y[i]);
  std::printf("downstream: T_w_b.t = (%.3f, %.3f, %.3f), Plus/Minus round-trip error %.2e\n",
              T_w_b.translation().x(), T_w_b.translation().y(), T_w_b.translation().z(), err);
  // A VLP-16 return 1 deg above the horizon (beams every 2 deg from -15 deg) is on ring 8.
  plucker::sensor::LidarScan scan;
  scan.points.emplace_back(10.0, 0.0, 10.0 * std::tan(1.0 * M_PI / 180.0));
  plucker::sensor::AssignRings(&scan, plucker::sensor::VLP16());
  std::printf("downstream: VLP-16 return at +1 deg elevation -> ring %d\n", scan.ring.at(0));
  return err < 1e-20 && scan.ring.at(0) == 8 ? 0 : 1;
}
