// A recorded camera + IMU sequence as the estimators read it: the rig, the IMU and its noise
// model, the frame times, and per frame the point and segment observations with their track ids
// (camera_observations.h); optionally the ground truth (body and camera trajectories and the 3D
// scene the track ids index). The simulator produces it (sim::ToCameraImuSequence); the files
// are io/sim_format.h (docs/sim-format.md).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "plucker/geometry/line_segment.h"
#include "plucker/geometry/se3.h"
#include "plucker/sensor/camera_observations.h"
#include "plucker/sensor/camera_rig.h"
#include "plucker/sensor/imu.h"

namespace plucker {
namespace sensor {

struct CameraImuGroundTruth {
  // Per frame (same indexing as CameraImuSequence::frame_times).
  std::vector<SE3d> T_w_c;  // = T_w_b[i] * rig.T_b_c
  std::vector<SE3d> T_w_b;
  std::vector<Eigen::Vector3d> v_w;                              // body velocity in the world frame
  Eigen::Vector3d initial_gyro_bias = Eigen::Vector3d::Zero();   // at the first IMU sample
  Eigen::Vector3d initial_accel_bias = Eigen::Vector3d::Zero();  // (ImuSample has them all)
  // The scene: PointObservation::point_id indexes points_w, SegmentObservation::line_id
  // segments_w.
  std::string scene_kind;  // a label, e.g. the simulator's "room" | "corridor" | "facades"
  std::vector<Eigen::Vector3d> points_w;
  std::vector<int> point_plane_ids;  // points_w[i] lies on planes_w[point_plane_ids[i]]
  std::vector<LineSegment3> segments_w;
  std::vector<Eigen::Vector4d> planes_w;  // (m, e): m . x + e = 0, |m| = 1
  Eigen::AlignedBox3d free_space_w;       // where the body moves
};

// The second camera of a stereo rig (docs/sim-format.md: cam1_points.txt, cam1_segments.txt):
// the same intrinsics and image size as the rig's camera (cam0), mounted at T_c0_c1 (cam1 in
// cam0's frame; Kalibr's T_cn_cnm1 is its inverse, T_c1_c0), its observations with cam0's track
// ids (the same scene point or segment: a left-right match).
struct SecondCamera {
  SE3d T_c0_c1;
  std::vector<PointObservation> points;      // sorted by frame
  std::vector<SegmentObservation> segments;  // sorted by frame
};

struct CameraImuSequence {
  CameraRig rig;
  ImuModel imu_model;
  ObservationModel observation_model;
  Eigen::Vector3d gravity_w{0.0, 0.0, -9.81};  // m/s^2, in the world frame
  std::vector<double> frame_times;             // s, increasing
  std::vector<ImuSample> imu;                  // increasing times
  std::vector<PointObservation> points;        // sorted by frame
  std::vector<SegmentObservation> segments;    // sorted by frame
  std::optional<CameraImuGroundTruth> ground_truth;
  std::optional<SecondCamera> cam1;  // a stereo rig's second camera
};

}  // namespace sensor
}  // namespace plucker
