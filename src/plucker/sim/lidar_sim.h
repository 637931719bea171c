// Simulation of a spinning multi-beam LiDAR on a vehicle driving through a LidarScene. No I/O.
//
// The sensor frame s: x forward, y left, z up, mounted `mount_height` above the ground on the
// vehicle. The beam pattern is given as plain numbers (LidarSimOptionsFor copies them from a
// sensor::LidarModel).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "plucker/geometry/se3.h"
#include "plucker/sensor/lidar_model.h"
#include "plucker/sensor/lidar_scan.h"
#include "plucker/sim/lidar_scene.h"

namespace plucker {
namespace sim {

struct VehicleTrajectoryOptions {
  double speed = 10.0;                // m/s along the route
  double corner_radius = 12.0;        // m, turns are circular arcs of this radius (clamped to fit)
  double mount_height = 1.73;         // m, sensor above the ground (KITTI HDL-64E)
  double pitch_roll_amplitude = 0.0;  // rad, slow sinusoidal pitch/roll (0 = flat)
  // Speed v(t) = speed + speed_variation * sin(2 pi t / speed_period): accelerations up to
  // 2 pi speed_variation / speed_period (0: constant speed). Needs speed_variation < speed.
  double speed_variation = 0.0;  // m/s
  double speed_period = 4.0;     // s
};

// Constant-speed motion along a closed route with corners rounded into circular arcs. The pose
// T_w_s(t) is continuous and smooth in t; the route loops.
class VehicleTrajectory {
 public:
  VehicleTrajectory(const std::vector<Eigen::Vector2d>& route,
                    const VehicleTrajectoryOptions& options = VehicleTrajectoryOptions());
  SE3d T_w_s(double t) const;
  double loop_length() const { return total_length_; }  // metres
  double loop_duration() const { return total_length_ / options_.speed; }
  double DistanceAt(double t) const;  // metres driven since t = 0

 private:
  struct Segment {  // a straight piece or an arc
    bool arc = false;
    Eigen::Vector2d start = Eigen::Vector2d::Zero();  // straight: start + s*dir
    Eigen::Vector2d dir = Eigen::Vector2d::UnitX();
    Eigen::Vector2d center = Eigen::Vector2d::Zero();  // arc
    double radius = 0, angle0 = 0, turn = 0;           // arc: angle0 + s/radius*sign(turn)
    double length = 0, s0 = 0;
  };
  VehicleTrajectoryOptions options_;
  std::vector<Segment> segments_;
  double total_length_ = 0.0;
};

struct LidarSimOptions {
  std::vector<double> elevation_rad;  // beams, ring 0 = lowest
  int azimuth_steps = 2000;           // firings per revolution
  double rate_hz = 10.0;
  double min_range = 0.5, max_range = 120.0;
  double range_noise_sigma = 0.0;  // m, Gaussian noise on the range
  // false: every point is measured from the pose at the scan start (T_w_s(t0)), time field empty.
  // true: firing k happens at t0 + k / (azimuth_steps * rate_hz) from the pose at that time, and
  //       scan.time holds that relative time (the points are still expressed in the frame of
  //       the pose at the firing, as a real sensor does: deskewing must undo this).
  bool distortion = false;
  // false: no rings, no spinning order (a Livox-like "generic" sensor): rays_per_scan rays, ray k
  // fired at k / (rays_per_scan * rate_hz) in a direction of the R2 low-discrepancy sequence
  // (azimuth over 360 deg, elevation uniform in [min_elevation_rad, max_elevation_rad]) that
  // continues from scan to scan (non-repeating); elevation_rad and azimuth_steps are unused, the
  // ring channel stays empty.
  bool spinning = true;
  double min_elevation_rad = 0.0, max_elevation_rad = 0.0;
  int rays_per_scan = 0;
  std::uint64_t seed = 1;
};

// The options that simulate `sensor` (beam pattern, rate, ranges, spinning or not) with Gaussian
// range noise and, if `distortion`, per-firing poses and point times.
LidarSimOptions LidarSimOptionsFor(const sensor::LidarModel& sensor, double range_noise_sigma,
                                   bool distortion, std::uint64_t seed = 1);

struct LidarSimStats {
  std::size_t rays = 0, hits = 0;
};

class LidarSimulator {
 public:
  LidarSimulator(const LidarScene& scene, const LidarSimOptions& options);

  // One sweep starting at time t0 (scan.timestamp = t0). Points are in the sensor frame of the
  // sweep start, or of their firing time with distortion (see LidarSimOptions::distortion).
  // Ordered like a KITTI .bin: ring by ring (ring 0 = lowest first), each ring one sweep in
  // azimuth, so that AssignRingsFromScanOrder works on the written .bin; ring and
  // intensity (a function of incidence angle) filled. Deterministic given (seed, frame_index).
  // The sweep starts facing forward (azimuth 0) and turns counter-clockwise seen from above,
  // like the KITTI .bin order.
  LidarScan Scan(const VehicleTrajectory& trajectory, double t0, std::size_t frame_index,
                 LidarSimStats* stats = nullptr) const;

 private:
  // The ray of direction d_s (sensor frame) from pose T_w_s: appends the hit, if any.
  void CastRay(const SE3d& T_w_s, const Eigen::Vector3d& d_s, double noise, LidarScan* scan) const;
  LidarScan NonSpinningScan(const VehicleTrajectory& trajectory, double t0,
                            std::size_t frame_index) const;
  const LidarScene& scene_;
  LidarSimOptions options_;
};

}  // namespace sim
}  // namespace plucker
