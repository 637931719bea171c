// VIO on a simulated Kannala-Brandt fisheye (sim::FisheyeRig): the raw points of the full image
// mapped into the pinhole view through the lens model (sensor::ToPinholeView) give a small ATE;
// the same raw pixels taken as pinhole pixels of the camera's K (what a pipeline assuming a
// pinhole would do) do not.
#include <gtest/gtest.h>

#include "plucker/eval/ate.h"
#include "plucker/odometry/visual_inertial_odometry.h"
#include "plucker/sensor/fisheye_rig.h"
#include "plucker/sim/camera_observations.h"

namespace plucker {
namespace odometry {
namespace {

struct FisheyeRun {
  double ate = 0.0;  // position + yaw, over the frames with a pose
  int posed = 0;
};

// map_points: through the lens into the view (else the raw pixels with the raw K as a pinhole).
FisheyeRun RunVio(const sim::CameraSimulation& s, bool map_points) {
  sensor::CameraImuSequence seq = sim::ToCameraImuSequence(s);
  if (map_points) {
    sensor::ToPinholeView(&seq);
  } else {
    seq.rig.fisheye.reset();  // raw pixels, K of the raw camera, segments dropped below
  }
  VisualInertialCalibration calib;
  calib.camera.K = seq.rig.K;
  calib.camera.width = seq.rig.width;
  calib.camera.height = seq.rig.height;
  calib.T_b_c = seq.rig.T_b_c;
  calib.imu = seq.imu_model;
  calib.gravity_magnitude = seq.gravity_w.norm();
  calib.pixel_sigma = seq.observation_model.pixel_sigma;
  VisualInertialOdometryOptions options;
  options.use_lines = false;
  VisualInertialOdometry vio(options, calib);
  std::vector<window::FrameInput> frames(seq.frame_times.size());
  for (std::size_t i = 0; i < frames.size(); ++i) frames[i].time = seq.frame_times[i];
  for (const auto& p : seq.points)
    if (p.point_id >= 0 && p.point_id % 2 == 0) frames[p.frame].points.push_back(p);
  std::size_t k = 0;
  for (const window::FrameInput& f : frames) {
    while (k < seq.imu.size() && (k == 0 || seq.imu[k - 1].t < f.time)) vio.AddImu(seq.imu[k++]);
    vio.AddFrame(f);
  }
  vio.Finish();
  std::vector<SE3d> gt, est;
  for (const VioFrameRecord& r : vio.RefinedTrajectory()) {
    if (!r.T_w_b) continue;
    gt.push_back(s.T_w_b_gt[r.frame]);
    est.push_back(*r.T_w_b);
  }
  FisheyeRun run;
  run.posed = static_cast<int>(est.size());
  if (est.size() >= 3)
    run.ate = eval::ComputeAte(gt, est, {eval::AlignmentMode::kPositionYaw}).translation_m.rmse;
  return run;
}

TEST(FisheyeVio, RawPointsThroughTheLensModelTrackTheRoom) {
  sim::CameraSimulationOptions o;
  o.num_frames = 60;
  o.rig = sim::FisheyeRig();  // points in the full image
  o.obs.observe_segments = false;
  const sim::CameraSimulation s = sim::SimulateCamera(o);
  const FisheyeRun mapped = RunVio(s, true);
  const FisheyeRun pinhole = RunVio(s, false);
  EXPECT_GT(mapped.posed, 40);
  EXPECT_LT(mapped.ate, 0.12);
  // Taken as pinhole pixels, the fisheye's points fail the bound (or never start).
  EXPECT_TRUE(pinhole.posed < 3 || pinhole.ate > 0.12) << pinhole.ate;
  RecordProperty("ate_mapped_m", std::to_string(mapped.ate));
  RecordProperty("ate_as_pinhole_m", std::to_string(pinhole.ate));
  std::printf("fisheye VIO ATE: mapped %.4f m (%d poses), as pinhole %.4f m (%d poses)\n",
              mapped.ate, mapped.posed, pinhole.ate, pinhole.posed);
}

}  // namespace
}  // namespace odometry
}  // namespace plucker
