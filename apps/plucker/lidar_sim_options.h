// The simulator's beam pattern and ranges from a sensor model (the sim layer does not depend on
// the lidar layer, so the app joins them). Shared by `plucker sim lidar` and the demo.
#pragma once

#include <cstdint>

#include "plucker/sensor/lidar_model.h"
#include "plucker/sim/lidar_sim.h"

namespace plucker {
namespace app {

inline sim::LidarSimOptions LidarSimOptionsFor(const sensor::LidarModel& sensor,
                                               double range_noise_sigma, bool distortion,
                                               std::uint64_t seed) {
  sim::LidarSimOptions options;
  options.elevation_rad = sensor.elevation_rad;
  options.azimuth_steps = sensor.azimuth_steps;
  options.rate_hz = sensor.rate_hz;
  options.min_range = sensor.min_range;
  options.max_range = sensor.max_range;
  options.range_noise_sigma = range_noise_sigma;
  options.distortion = distortion;
  options.spinning = sensor.spinning;
  options.min_elevation_rad = sensor.min_elevation_rad;
  options.max_elevation_rad = sensor.max_elevation_rad;
  options.rays_per_scan = sensor.rays_per_scan;
  options.seed = seed;
  return options;
}

}  // namespace app
}  // namespace plucker
