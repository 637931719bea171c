// Camera observations of a simulated scene, and the whole camera/IMU simulation.
//
// Pixel coordinates: u right, v down, the image is [0, width - 1] x [0, height - 1] (pixel
// centres at integers). Depth is the camera-frame z. A point is visible when
// min_depth <= z <= max_depth and its projection lies in the image. A segment is clipped in 3D
// against the view frustum (near plane z = min_depth, far plane z = max_depth and the four side
// planes through the image borders), so the clipped endpoints project inside the image and onto
// the projection of the full line; it is kept if the clipped length is >= min_segment_px.
// Endpoint order is kept: s_px comes from the a_w side, e_px from the b_w side.
// Noise: i.i.d. Gaussian pixel_sigma on every coordinate. Outliers (id -1): uniformly random
// pixels / random segments inside the image, outlier_ratio = outliers / all observations.
// No occlusion test: the scenes are convex from the free space (frames protrude by centimetres).
// A fisheye rig (rig.fisheye, FisheyeRig()) is observed as a real fisheye front end delivers:
// points projected through the Kannala-Brandt lens into the full raw image (visible when
// min_depth <= z <= max_depth, within the lens's valid angle and inside the raw image; noise and
// outliers in raw pixels), or with points_in_view like the segments: in the undistorted pinhole
// view (FisheyeView::view_K and size), clipped against its frustum, noise in view pixels.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "plucker/geometry/se3.h"
#include "plucker/sensor/camera_imu_sequence.h"
#include "plucker/sensor/camera_observations.h"
#include "plucker/sensor/camera_rig.h"
#include "plucker/sim/imu.h"
#include "plucker/sim/scene.h"
#include "plucker/sim/trajectory.h"

namespace plucker {
namespace sim {

// R_b_c of the default rig: camera z (forward) = body x, camera x (right) = -body y,
// camera y (down) = -body z.
Eigen::Matrix3d DefaultRotationBodyCamera();
// The default extrinsic T_b_c: DefaultRotationBodyCamera() and t_b_c = (0.05, -0.02, 0.01) m.
SE3d DefaultBodyCameraPose();

// The pose with its quaternion re-normalised to a fixed point of SE3d's normalisation, so that
// writing its coefficients with %.17g and reading them back gives the identical pose. Every pose
// SimulateCamera returns is canonical.
SE3d CanonicalPose(const SE3d& T);

// The simulated rig: a 640 x 480 pinhole with fx = fy = 400 and the principal point at the
// image centre, mounted at DefaultBodyCameraPose().
sensor::CameraRig DefaultRig();

// The simulated fisheye (`plucker sim camera --camera-model kb`): TUM-VI's cam0 as Kalibr
// calibrated it, a 512 x 512 Kannala-Brandt camera, fx = fy = 190.98, principal point
// (254.93, 256.90), k1..k4 = (0.003482, 0.000715, -0.002053, 0.000203): 154 deg across the
// image's width, the lens's 180 deg (its valid angle) reached before the corners. Mounted at
// DefaultBodyCameraPose(). The segments' pinhole view is 512 x 512 with the principal point at
// the image centre and fx = fy = 256 / tan(view_fov_deg / 2) (view_fov_deg in (0, 170)):
// kDefaultViewFovDeg gives the lens's own resolution at the centre (fx = 191, the view of
// vision::Undistorter's default).
constexpr double kDefaultViewFovDeg = 107.0;
sensor::CameraRig FisheyeRig(double view_fov_deg = kDefaultViewFovDeg, bool points_in_view = false);

// Observations (sensor/camera_observations.h): point_id indexes Scene::points_w, line_id
// Scene::segments_w; -1 is an outlier.

// The observation settings are the sensor-level description the sequence files store.
using ObservationOptions = sensor::ObservationModel;

// A world segment clipped to the view frustum of a camera at T_w_c.
struct ClippedSegment {
  double s0 = 0.0, s1 = 1.0;  // kept parameter interval of a_w + s (b_w - a_w), s0 < s1
  Eigen::Vector3d a_c = Eigen::Vector3d::Zero(), b_c = Eigen::Vector3d::Zero();  // clipped, camera
  Eigen::Vector2d s_px = Eigen::Vector2d::Zero(), e_px = Eigen::Vector2d::Zero();  // projections
};

// Noise-free projection of p_w, or nullopt when it is not visible (see the file comment).
std::optional<Eigen::Vector2d> ProjectVisiblePoint(const Eigen::Vector3d& p_w, const SE3d& T_w_c,
                                                   const sensor::CameraRig& rig, double min_depth,
                                                   double max_depth);
// Clips in 3D (Liang-Barsky on the segment parameter); nullopt if nothing is left.
std::optional<ClippedSegment> ClipSegmentToImage(const LineSegment3& segment_w, const SE3d& T_w_c,
                                                 const sensor::CameraRig& rig, double min_depth,
                                                 double max_depth);

struct ObservationStats {
  int num_point_inliers = 0, num_point_outliers = 0;
  int num_segment_inliers = 0, num_segment_outliers = 0;
};

struct CameraObservations {
  std::vector<sensor::PointObservation> points;  // sorted by frame; inliers by id, then outliers
  std::vector<sensor::SegmentObservation> segments;  // same order
  ObservationStats stats;
};

// Observes the scene from every camera pose (frame i = T_w_c[i]). Throws std::invalid_argument
// for invalid options or rig.
CameraObservations ObserveScene(const Scene& scene, const sensor::CameraRig& rig,
                                const std::vector<SE3d>& T_w_c, const ObservationOptions& options,
                                std::uint64_t seed);

// Ground truth and measurements of one simulated camera + IMU sequence.
struct CameraSimulation {
  Scene scene;
  sensor::CameraRig rig;
  ImuOptions imu_options;           // the noise model the IMU samples were drawn with
  ObservationOptions obs_options;   // the pixel noise / outlier model of the observations
  std::vector<double> frame_times;  // s
  std::vector<SE3d> T_w_c_gt;       // = T_w_b_gt[i] * rig.T_b_c (to the last bit)
  std::vector<SE3d> T_w_b_gt;
  std::vector<Eigen::Vector3d> v_w_gt;  // body velocity at the frame times
  std::vector<sensor::PointObservation> points;
  std::vector<sensor::SegmentObservation> segments;
  std::vector<sensor::ImuSample> imu;
  ObservationStats stats;
  // CameraSimulationOptions::T_c0_c1: the second camera's observations (its own noise stream),
  // with their statistics.
  std::optional<sensor::SecondCamera> cam1;
  ObservationStats cam1_stats;
};

struct CameraSimulationOptions {
  SceneOptions scene;
  TrajectoryOptions trajectory;  // duration is overwritten with (num_frames - 1) / frame_rate_hz
  ImuOptions imu;
  ObservationOptions obs;
  sensor::CameraRig rig = DefaultRig();
  int num_frames = 100;
  double frame_rate_hz = 10.0;
  bool simulate_imu = true;
  std::uint64_t seed = 1;
  // A stereo rig: a second camera with the rig's pinhole and image at T_c0_c1 (cam1 in cam0's
  // frame; StereoPose(b): b metres along cam0's +x, EuRoC-like for b = 0.11), observing the same
  // scene (pinhole rigs only). Unset: no second camera, the output as without the option.
  std::optional<SE3d> T_c0_c1;
};

// The second camera of a stereo rig `baseline_m` along the first camera's +x, axes parallel.
SE3d StereoPose(double baseline_m);

// Scene, trajectory, IMU and observations, each from its own stream derived from options.seed.
// Frame i is at t_i = i / frame_rate_hz. Throws std::invalid_argument for invalid options.
CameraSimulation SimulateCamera(const CameraSimulationOptions& options);

// The simulation as a recorded sequence with its ground truth (what io/sim_format.h writes).
sensor::CameraImuSequence ToCameraImuSequence(const CameraSimulation& simulation);

// The fastest motion of a simulation: body speed at the frame times (m/s) and turn rate between
// consecutive frames (rad/s).
struct MotionStats {
  double max_speed = 0.0, max_turn_rate = 0.0;
};
MotionStats MeasureMotion(const CameraSimulation& simulation);

}  // namespace sim
}  // namespace plucker
