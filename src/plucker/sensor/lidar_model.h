// Spinning multi-beam LiDAR models (beam elevation tables) and ring assignment.
//
// Rings are numbered 0..N-1 from the LOWEST beam up. A point's elevation is
// atan2(z, sqrt(x^2 + y^2)) in the sensor frame (x forward, y left, z up).
//
// Which ring assignment to use:
//   - Scans with a ring field (PCD from a driver, the simulator): keep it.
//   - KITTI .bin (HDL-64E): use AssignRingsFromScanOrder. The .bin stores the points beam by
//     beam, each beam one sweep in azimuth; splitting where the azimuth wraps recovers the true
//     laser of every point. The HDL-64E firing table is non-uniform and the KITTI points are
//     motion-compensated, so AssignRings (nearest elevation in the approximate table) mislabels
//     a few percent of the points near ring boundaries.
//   - Other scans without ring (e.g. a PCD without ring): AssignRings with the user's --sensor,
//     or AutoDetectSensor for --sensor auto.
#pragma once

#include <string>
#include <vector>

#include "plucker/sensor/lidar_scan.h"

namespace plucker {
namespace sensor {

struct LidarModel {
  std::string name;
  std::vector<double> elevation_rad;  // ring 0 = lowest, increasing
  double min_range = 0.5;             // metres
  double max_range = 120.0;           // metres
  int azimuth_steps = 2000;           // firings per revolution
  double rate_hz = 10.0;              // revolutions per second
  // false: no rings and no spinning order (Livox-like, "generic"): elevation_rad is empty, the
  // field of view is min/max_elevation_rad over 360 deg of azimuth, rays_per_scan rays per scan
  // in a non-repeating order (sim/lidar_sim.h), features from local geometry
  // (lidar/geometric_features.h).
  bool spinning = true;
  double min_elevation_rad = 0.0, max_elevation_rad = 0.0;  // generic only
  int rays_per_scan = 0;                                    // generic only

  int num_rings() const { return static_cast<int>(elevation_rad.size()); }
  // Nearest beam to `elevation_rad`, or -1 when it lies outside the table by more than half of
  // the adjacent spacing (or is not finite).
  int RingFromElevation(double elevation_rad) const;
};

// Velodyne HDL-64E as in KITTI: 64 beams, +2.0 deg .. -24.33 deg. Documented approximation of
// the non-uniform factory table: upper block 32 beams uniformly +2.0 .. -8.33 deg, lower block 32
// beams uniformly -8.83 .. -24.33 deg. 0.9 .. 120 m, 2083 azimuth steps (0.1728 deg at 10 Hz).
LidarModel HDL64();
// Velodyne VLP-32C (Ultra Puck): the 32 non-uniform factory elevations, +15 .. -25 deg, dense
// around -1 deg. 0.5 .. 200 m, 1800 azimuth steps (0.2 deg at 10 Hz).
LidarModel VLP32();
// Velodyne VLP-16 (Puck): -15 .. +15 deg every 2 deg. 0.5 .. 100 m, 1800 azimuth steps.
LidarModel VLP16();
// Ouster OS1-64 / OS1-128, uniform beam spacing over the OS1 datasheet's vertical field of view:
// 64 beams over +16.6 .. -16.6 deg (33.2 deg), 128 over +22.5 .. -22.5 deg (45 deg); 1024
// columns per revolution at 10 Hz, 0.5 .. 120 m. Later revisions (Rev 6/7) have other fields of
// view and a real unit's beam_altitude_angles differ: clouds from the driver carry a ring field,
// which is used instead of this table.
LidarModel OS1_64();
LidarModel OS1_128();
// A cloud without rings and without a spinning order (Livox-like): 360 deg azimuth, elevations
// -25 .. +15 deg, 40000 rays per scan at 10 Hz, 0.5 .. 100 m. spinning = false.
LidarModel GenericLidar();
// "hdl64" | "vlp32" | "vlp16" | "os1-64" | "os1-128" | "generic" (case-insensitive); throws
// std::invalid_argument naming the accepted names otherwise.
LidarModel LidarModelFromName(const std::string& name);
// The accepted names, "hdl64, vlp32, vlp16, os1-64, os1-128, generic".
const char* LidarModelNames();

struct RingAssignmentStats {
  int rings_found = 0;         // distinct rings that received points
  std::size_t unassigned = 0;  // points with ring -1 (outside the table)
};

// Fills scan->ring from each point's elevation (nearest beam, -1 outside the table). Does nothing
// (returns rings_found from the existing field) when the scan already has a ring field.
RingAssignmentStats AssignRings(LidarScan* scan, const LidarModel& model);

// Fills scan->ring from the firing order: a new ring starts where the azimuth wraps from the
// end of a revolution back to its start. The azimuth (FastAtan2) is measured in the sweep
// direction from the seam where the beams start (both found from the data: the direction is the
// sign that most steps between consecutive points take; the seam is where the first ring starts,
// KITTI: the front, az ~ 0, counter-clockwise); a wrap is a drop by more than
// `wrap_threshold_rad` after the ring has swept more than half a turn.
// Ring numbers are then flipped if needed so that ring 0 is the lowest (by mean elevation).
// Overwrites an existing ring field. For scans stored in firing order (KITTI .bin). The split is
// taken on the points' coordinates, with the azimuths computed only where a decision is close
// (lidar_model.cc): the same rings as from every point's azimuth, at about half the cost.
struct ScanOrderOptions {
  double wrap_threshold_rad = 3.14159265358979;  // azimuth jump (backwards) that starts a ring
  int min_points_per_ring = 16;  // shorter fragments are merged into the ring before them
};
RingAssignmentStats AssignRingsFromScanOrder(LidarScan* scan,
                                             const ScanOrderOptions& options = ScanOrderOptions());

// Guesses the sensor from the elevation histogram (vertical field of view and number of
// distinct elevation peaks): returns HDL64, VLP32 or VLP16. `confidence` (optional, 0..1) says
// how well the histogram matched. Scans with < 100 points return VLP16 with confidence 0.
LidarModel AutoDetectSensor(const LidarScan& scan, double* confidence = nullptr);

}  // namespace sensor
}  // namespace plucker
