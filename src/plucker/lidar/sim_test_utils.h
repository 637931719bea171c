// Tests only: the simulator's options for a sensor model (the sim layer does not know
// sensor::LidarModel; apps/plucker/lidar_sim_options.h does the same for the app).
#pragma once

#include <algorithm>

#include "plucker/sensor/lidar_model.h"
#include "plucker/sim/lidar_sim.h"

namespace plucker {
namespace lidar {

inline sim::LidarSimOptions SimOptionsFor(const sensor::LidarModel& m, bool distortion,
                                          double range_noise_sigma = 0.01) {
  sim::LidarSimOptions o;
  o.elevation_rad = m.elevation_rad;
  o.azimuth_steps = std::max(8, m.azimuth_steps);
  o.rate_hz = m.rate_hz;
  o.min_range = m.min_range;
  o.max_range = m.max_range;
  o.spinning = m.spinning;
  o.min_elevation_rad = m.min_elevation_rad;
  o.max_elevation_rad = m.max_elevation_rad;
  o.rays_per_scan = m.rays_per_scan;
  o.range_noise_sigma = range_noise_sigma;
  o.distortion = distortion;
  return o;
}

}  // namespace lidar
}  // namespace plucker
