// A simulated camera run as the online visual-inertial odometry's input (not installed): its
// calibration, IMU samples and per-frame observations, shared by the odometry tests.
#pragma once

#include <cstddef>
#include <vector>

#include "plucker/odometry/visual_inertial_odometry.h"
#include "plucker/sim/camera_observations.h"

namespace plucker {
namespace odometry {

struct VioTestInput {
  VisualInertialCalibration calib;
  std::vector<sensor::ImuSample> imu;
  std::vector<window::FrameInput> frames;
  std::vector<SE3d> gt_T_w_b;
};

// every_other_point: only the even point ids (a lighter map for the longer runs).
inline VioTestInput VioInputFromSimulation(const sim::CameraSimulation& s, bool every_other_point) {
  VioTestInput in;
  in.calib.camera.K = s.rig.K;
  in.calib.camera.width = s.rig.width;
  in.calib.camera.height = s.rig.height;
  in.calib.T_b_c = s.rig.T_b_c;
  in.calib.imu = s.imu_options.model;
  in.calib.gravity_magnitude = s.imu_options.gravity_w.norm();
  in.calib.pixel_sigma = s.obs_options.pixel_sigma;
  in.imu = s.imu;
  in.frames.resize(s.frame_times.size());
  for (std::size_t i = 0; i < in.frames.size(); ++i) in.frames[i].time = s.frame_times[i];
  for (const auto& p : s.points)
    if (!every_other_point || p.point_id % 2 == 0) in.frames[p.frame].points.push_back(p);
  in.gt_T_w_b = s.T_w_b_gt;
  return in;
}

// Feeds the frames as a driver does: the IMU up to each frame's time, then the frame. Calls
// on_frame(vio, result) after each frame; it returns false to stop early (no Finish then).
template <typename OnFrame>
void FeedVio(VisualInertialOdometry& vio, const VioTestInput& in, OnFrame on_frame) {
  std::size_t k = 0;
  for (const window::FrameInput& f : in.frames) {
    while (k < in.imu.size() && (k == 0 || in.imu[k - 1].t < f.time)) vio.AddImu(in.imu[k++]);
    if (!on_frame(vio, vio.AddFrame(f))) return;
  }
  vio.Finish();
}

}  // namespace odometry
}  // namespace plucker
