// Online monocular point + line visual-inertial odometry (docs/vio.md): the pipeline of
// `plucker vio` as a library, fed one IMU sample and one frame at a time as a driver delivers
// them. The algorithm, per frame:
//   initialise  (visual_inertial_initializer.h) static when the log starts still (gravity, gyro
//               bias, accel bias along gravity), decided once the motion starts; else dynamic:
//               a vision-only window from a two-view start checked against the gyroscope,
//               aligned with the preintegrated IMU (scale, gravity, velocities, gyro bias) at
//               each new keyframe; then the window starts on the initialisation's keyframes and
//               the frames buffered after its last one are run through it (catch-up);
//   track       window AddFrame: IMU prediction, visual tracking, keyframe decision,
//               triangulation, solve with the IMU factors, marginalization.
//
// Causality: the result returned for frame k uses only the IMU samples and frames given up to
// that call (the samples up to the frame's time must have been given: a driver waits for the
// IMU to reach the image's timestamp). Before the start the result has no pose (status
// kInitializing); the frames' observations are buffered until the initialisation decides, then
// released (memory bounded by the initialisation's span and the window; what grows with the
// sequence is one small record per frame, RefinedTrajectory(), and the window's IMU samples).
//
// Two trajectories: the per-frame (online) poses of the results, and RefinedTrajectory(): every
// frame with a pose, the frames before the window's start backfilled once it starts (localized
// against its first map, the aligned visual poses of the dynamic start), which an online output
// cannot hold. Finish() ends the input: an initialisation still waiting decides on what it has
// (a log that is still throughout starts static).
//
// No I/O, no printing, no timing: the caller times the calls (observers announce the stages).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "plucker/geometry/se3.h"
#include "plucker/odometry/frame_observer.h"
#include "plucker/sensor/camera.h"
#include "plucker/sensor/imu.h"
#include "plucker/vision/image_frontend.h"
#include "plucker/vision/undistort.h"
#include "plucker/window/sliding_window_estimator.h"

namespace plucker {
namespace odometry {

struct VisualInertialOdometryOptions {
  bool use_lines = true;
  int window = 10;  // keyframes in the window
  // The poses-only prior (DSO pattern, the velocity and bias blocks and the IMU factor kept;
  // docs/vio.md); false: the prior on the landmarks of the marginalized keyframe (slower).
  bool prior_on_poses_only = true;
  // Keyframes and solver budget: the IMU bridges longer gaps between keyframes than VO needs.
  int iterations = 4;
  double keyframe_parallax_px = 20.0;
  int min_tracked = 20;            // a keyframe when fewer landmarks are tracked
  double min_tracked_ratio = 0.3;  // ... or fewer than this share of the frame's observations
  // ... or when the frame has turned this much from the newest keyframe (deg; 0: off), under a
  // fast turn only: some frame since that keyframe turned at keyframe_min_turn_rate_deg_s or
  // faster from its previous frame (0: at any rate). Fast turns: the aggressive corridor at 30 Hz
  // (1.2 rad/s, 5 m/s looking down the corridor) kept the median parallax under 20 px for a second
  // while the tracks ended, and the dynamic start's vision-only run lost scale along its 4.5 s
  // (0.93 -> 0.79 of the true step). 10 deg at any rate fixes it but costs the 10 Hz corridor
  // (seed 1: 0.074 -> 0.104 m), where the 13 deg/s turns gave rotation keyframes too; the normal
  // simulated motions turn at up to 31 deg/s, the aggressive corridor at up to 70, hence 45
  // (docs/results/vio.md). Applies to the window and to the dynamic start's vision-only run.
  // With the start's bundle adjustment on, both on by default: the fast rows' mean ATE 0.0403 ->
  // 0.0358 m, worst 0.441 -> 0.179 m; normal motion byte-identical (docs/results/vio.md).
  double keyframe_max_rotation_deg = 10.0;
  double keyframe_min_turn_rate_deg_s = 45.0;  // deg/s
  // The dynamic start's vision-only run alone: its rotation keyframe bound (deg; 0: the window's
  // keyframe_max_rotation_deg), at keyframe_min_turn_rate_deg_s or faster.
  double init_keyframe_max_rotation_deg = 0.0;
  // Keyframes observing a segment track before its line is triangulated
  // (window::SlidingWindowOptions::min_line_views). A two-view line is exactly determined (two
  // planes always meet): its errors are not averaged, and on the fisheye's 107 deg view
  // (f = 189 px) those lines made the VIO worse than points only. 3 fixes that on the room
  // (seeds 1-5: 0.0231 -> 0.0194 m, = points only) but costs the corridor's view (seed 1:
  // 0.0816 -> 0.1104 m) and the full-image fisheye (6 %): opt-in (docs/results/fisheye.md).
  int min_line_views = 2;
  // window::SlidingWindowOptions::two_view_line_sigma_scale: a two-view line's observations
  // weighed down (sigma x this) until a third keyframe sees it (1: off).
  double two_view_line_sigma_scale = 1.0;
  bool recheck_two_view_lines = false;       // window::SlidingWindowOptions::recheck_two_view_lines
  double two_view_min_plane_angle_px = 0.0;  // window::SlidingWindowOptions::, the same (0: off)
  // The window's line endpoint sigma: the calibration's pixel sigma times this (1: as the points).
  // On the MH_05 images against ground-truth cameras (docs/results/vio.md, session 22) the line
  // tracks' endpoint distances have 0.59x the points' robust sigma (0.74x their RMS).
  double line_sigma_scale = 1.0;
  // window::SlidingWindowOptions::keep_marginalized_lines (false: the marginalized keyframe's line
  // observations are dropped, as PL-VIO does, instead of going into the prior).
  bool keep_marginalized_lines = true;
  double max_imu_factor_span_s = 1.0;
  double gyro_bias_prior_sigma = 0.01;
  double accel_bias_prior_sigma = 0.1;
  double velocity_prior_sigma = 0.1;
  // Per-frame tracking fuses the IMU prediction (window::InertialOptions, m/s; 0: vision only).
  double tracking_velocity_sigma = 0.02;

  int init_min_keyframes = 10;  // dynamic initialisation: keyframes before the alignment
  int init_max_keyframes = 60;  // ... and the most it waits for
  // After the first successful alignment, the vision-only run goes on for this many keyframes
  // more (at most init_max_keyframes) and is aligned again, so that the start (and its bundle
  // adjustment, init_ba_iterations) sees more of the motion; the first alignment is kept when
  // the run ends or the second fails. 0: off, the default (docs/results/vio.md, MH_05).
  int init_extend_keyframes = 0;
  // The extension above waits instead (or also) for the body to turn this angle from the run's
  // first keyframe (the gyroscope, at the first alignment's gyro bias): the start's bundle
  // adjustment separates the gravity tilt from the accelerometer bias only once the body has
  // turned. A start that has turned as much at its first alignment is not extended; one that
  // does not turn as much within init_max_keyframes keyframes or init_extend_max_seconds
  // (after the first alignment's newest keyframe; 0: no bound) keeps its first alignment.
  // Default 60 deg / 3 s (with init_ba_iterations 20, init_max_keyframes 60): MH_05 0.0656 ->
  // 0.0389 m, the simulated rows better on average (docs/results/vio.md); 0: off.
  double init_extend_min_rotation_deg = 60.0;
  double init_extend_max_seconds = 3.0;
  // The dynamic start's vision-only window weighs its two-view lines with this
  // (window::SlidingWindowOptions::two_view_line_sigma_scale; two_view_line_sigma_scale applies
  // when this is 0, the default).
  double init_two_view_line_sigma_scale = 0.0;
  // The dynamic start's alignment waits until its keyframes span this long (s; 0: off). Under the
  // fast room's 4.3 rad/s turns the keyframes came 1.7 frames apart at 30 Hz: 10 keyframes spanned
  // 0.57 s and the gyro bias fitted the vision-only run's rotation error (0.021 rad/s against 0;
  // 1 s: 0.014). Normal starts span more (the 10 Hz corridor 8.7 s, MH_05 1.4 s).
  double init_min_span_s = 1.0;
  double init_min_excitation = 0.25;  // m/s^2
  // The two-view start's rotation must agree with the gyroscope's (integrated at zero bias)
  // within this angle plus init_gyro_bias_bound times the time between the two frames.
  double init_max_rotation_disagreement_deg = 1.0;
  double init_gyro_bias_bound = 0.1;  // rad/s, the largest gyro bias expected before it is known
  // The dynamic start's search tests at most this many pairs (two-view RANSACs) a frame (0: no
  // bound); the rest wait, in order, for the next frames: the start is the unbounded search's,
  // decided some frames later when the budget binds. While the search runs more than 5 frames
  // behind, a pair needs a rotated parallax (the upper median, over the common point tracks, of
  // the pixel distance between the second frame's observation and the first's ray turned by the
  // gyroscope at zero bias) of at least init_pair_min_rotated_parallax_px before its RANSAC (0:
  // not tested): the cheap test that lets a search that cannot pass the two-view parallax test
  // (15 px) catch up. (Not always: a bas-relief pair of the pinhole corridor passed at 3.4 px.)
  int init_pair_budget = 0;
  double init_pair_min_rotated_parallax_px = 0.0;  // px
  // The visual-inertial bundle adjustment of the dynamic start over all the alignment's
  // keyframes (visual_inertial_start_ba.h): its iteration budget (default 20; 0: off, the window
  // starts on the aligned states) and its priors on the first keyframe's accelerometer bias (m/s^2,
  // weak: the alignment's bias carries its gravity tilt) and velocity (m/s).
  int init_ba_iterations = 20;
  double init_ba_accel_bias_prior_sigma = 0.5;
  double init_ba_velocity_prior_sigma = 0.5;
  // Given biases for the start's bundle adjustment (empty: off, the default; only with
  // init_ba_iterations > 0 and a dynamic start): every keyframe of the solve starts from them,
  // the first keyframe's prior is centred on them (accel: init_ba_accel_bias_prior_sigma; gyro:
  // held, 1e-4 rad/s), and the window's first prior on the solve's result (accel_bias_prior_sigma).
  // A diagnostic with a ground truth's biases, or the biases of an earlier run over the same data
  // (scripts/vio_two_pass.sh; docs/results/vio.md, MH_05).
  std::optional<Eigen::Vector3d> init_accel_bias;  // m/s^2, body
  std::optional<Eigen::Vector3d> init_gyro_bias;   // rad/s, body
  // A frame whose median point displacement against the previous frame exceeds this moves
  // (vetoes the static initialisation over its IMU block; else the window's zero-motion update).
  double image_still_px = 3.0;
  // ... measured, for the static test, against the newest earlier frame at least this much older
  // (0.1 s: the previous frame at 10 Hz or slower). Against the previous frame only, a slow start
  // down a corridor moved the points under image_still_px between two 20 Hz frames: the still
  // span ran 0.75 s into the motion and its gravity was 2 deg off (docs/vio.md).
  double image_still_span_s = 0.1;  // s
  // The still test's bound on a 0.25 s block's accelerometer spread (inertial::StaticInitOptions
  // max_accel_std, whose 1.5 m/s^2 a drone's rotors exceed at rest): EuRoC V1_01 standing still
  // (ground truth under 1 mm) gives 1.39-1.62 m/s^2 in its third block depending on where the
  // block grid falls (the first frame's time, moved by a Kalibr timeshift_cam_imu), its take-off
  // 2.45-2.75 m/s^2.
  double static_max_accel_std = 2.0;  // m/s^2
  // Image front end of AddImage: the speed settings of `plucker vo --images` (docs/vo.md).
  int max_point_tracks = 200;
  double point_min_distance_px = 20.0;
  double point_detect_below_share = 1.0;  // new corners only under this share of the tracks
  int line_max_segments = 60;             // longest segments kept per image (0: all)
  double line_detection_scale = 0.5;      // image scale of the segment detection
  int line_flow_samples = 3;              // points per segment followed by optical flow
  // Online estimation of the camera-body extrinsic (window::InertialOptions, docs/vio.md), with
  // a prior on the given T_b_c (sigmas in rad and m); held until the window has rotated this much
  // about two axes (0: free from the start).
  bool estimate_extrinsic = false;
  double extrinsic_rotation_sigma = 0.05;
  double extrinsic_translation_sigma = 0.02;
  double extrinsic_min_rotation_deg = 0.0;
  // Online estimation of the camera-IMU time offset td (window::InertialOptions, Kalibr's
  // convention t_imu = t_cam + td), from time_offset_s with a prior of this sigma (s).
  bool estimate_time_offset = false;
  double time_offset_s = 0.0;
  double time_offset_prior_sigma_s = 0.02;

  // Empty when usable, else which ranges are violated.
  std::string Problem() const;
  void Check() const;  // throws std::invalid_argument with Problem()
};

// The sensors. `camera`: the raw camera of AddImage (its images are undistorted to the pinhole
// camera.K, the pixels of the observations given to AddFrame).
struct VisualInertialCalibration {
  sensor::Camera camera;
  SE3d T_b_c;  // the camera in the body (IMU) frame
  sensor::ImuModel imu;
  double gravity_magnitude = 9.81;  // m/s^2
  double pixel_sigma = 1.0;         // observation noise (at least 0.5 px is used)
};

enum class VioStatus {
  kInitializing,      // no pose yet (buffered for the initialisation)
  kStarted,           // the window started at this frame (the initialisation's last frame)
  kTracking,          // the window tracked the frame
  kImuOnly,           // too little tracked: the IMU prediction
  kStationary,        // the zero-motion update (a standing body)
  kSkippedNoImu,      // the IMU does not cover the frame
  kSkippedNonFinite,  // no finite pose
  kFailed,            // the window could not start (message); later frames fail too
};
const char* ToString(VioStatus status);

// What the refined trajectory holds for a frame (the JSON statuses of `plucker vio`).
enum class VioFrameKind {
  kBeforeInitialization,   // no pose, or (with a pose) the next frame's pose carried back
  kInitialization,         // the initialisation's pose (window keyframe or aligned, localized)
  kLocalizedBeforeWindow,  // localized against the window's first map
  kWindow,                 // the window's per-frame result (status in VioStatus)
};

// One frame of the refined trajectory (see RefinedTrajectory()).
struct VioFrameRecord {
  int frame = 0;  // index among the frames given
  double time = 0.0;
  VioFrameKind kind = VioFrameKind::kBeforeInitialization;
  VioStatus status = VioStatus::kInitializing;  // kind == kWindow: the window's outcome
  std::optional<SE3d> T_w_b;
  bool keyframe = false;
  std::optional<window::WindowFrameResult> window;  // kind == kWindow and not skipped
  std::string skip_reason;                          // kSkippedNoImu
};
std::string ToString(const VioFrameRecord& record);  // the JSON status string

struct VioFrameResult {
  int frame = 0;
  double time = 0.0;
  VioStatus status = VioStatus::kInitializing;
  std::optional<SE3d> T_w_b;  // online pose (none while initialising or skipped)
  Eigen::Vector3d v_w = Eigen::Vector3d::Zero();
  sensor::ImuBias bias;
  std::optional<window::WindowFrameResult> window;  // this frame's window statistics
  int observed_points = 0, observed_segments = 0;   // the frame's input
  // Frames whose refined records became final in this call, oldest first (at the start: all the
  // buffered frames; then this frame).
  std::vector<VioFrameRecord> settled;
  // Frames without a visual update up to this one, this one included (kImuOnly in a row; 0
  // when this frame was tracked, stationary or is not settled yet).
  int imu_only_run = 0;
  std::string message;  // kFailed
};

// Frames first..last (indices among the frames given, times t_first..t_last) in a row without a
// visual update: the window predicted them from the IMU alone (status kImuOnly; a stationary
// frame has the zero-motion update and does not count).
struct VioImuOnlyStretch {
  int first = 0, last = 0;
  double t_first = 0.0, t_last = 0.0;
  int frames() const { return last - first + 1; }
};

// The run's counts over the settled frames (see RefinedTrajectory()).
struct VioStatistics {
  int settled_frames = 0;     // frames whose outcome is final
  int window_frames = 0;      // ... of which the window ran (tracked, IMU-only or stationary)
  int tracked_frames = 0;     // with a visual update
  int imu_only_frames = 0;    // without one (kImuOnly)
  int stationary_frames = 0;  // the zero-motion update
  int skipped_frames = 0;     // kSkippedNoImu, kSkippedNonFinite
  std::vector<VioImuOnlyStretch> imu_only_stretches;  // in order, every stretch
  // imu_only_frames / window_frames (0 without window frames).
  double ImuOnlyShare() const;
};

// What the initialisation did, for reports.
struct VioInitEvent {
  std::string event;  // static_test | wait | alignment | extension | restart
  int frame = -1;     // -1: none
  std::string status, message, reason;
  int keyframes = 0;
  double scale = 0.0;
  bool still = false;  // static_test succeeded: the three below are set
  double still_seconds = 0.0;
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero(), up_b = Eigen::Vector3d::Zero();
};

// What the dynamic start's bundle adjustment did (visual_inertial_start_ba.h).
struct StartAdjustmentSummary {
  bool ran = false, ok = false;
  int keyframes = 0, points = 0, lines = 0, iterations = 0;
  double final_cost = 0.0;
  double tilt_change_deg = 0.0;  // gravity direction in the newest keyframe's body, moved by
  double scale_change = 1.0;     // distance first to newest keyframe, after / before
};

struct VioInitialization {
  bool done = false;
  std::string method;  // static | dynamic
  int first = -1, second = -1;
  sensor::BodyState state_first;
  std::vector<VioInitEvent> events;
  StartAdjustmentSummary adjustment;  // the start's bundle adjustment (init_ba_iterations > 0)
};

class VisualInertialOdometry {
 public:
  // Throws std::invalid_argument for invalid options.
  VisualInertialOdometry(const VisualInertialOdometryOptions& options,
                         const VisualInertialCalibration& calibration);
  ~VisualInertialOdometry();
  VisualInertialOdometry(const VisualInertialOdometry&) = delete;
  VisualInertialOdometry& operator=(const VisualInertialOdometry&) = delete;

  // Times increasing across calls; std::invalid_argument otherwise (nothing changed).
  void AddImu(const sensor::ImuSample& sample);
  // A raw 8-bit grayscale image of calibration.camera: undistorted, the image front end
  // (vision/image_frontend.h), then AddFrame. Throws std::invalid_argument (nothing changed) for
  // an empty image or one of another size.
  VioFrameResult AddImage(double t, const cv::Mat& image,
                          const vision::FrontendObserver& frontend_observer = {},
                          const window::StageObserver& window_observer = {});
  // A frame's observations (undistorted pixels of camera.K, track ids), times increasing.
  VioFrameResult AddFrame(const window::FrameInput& frame,
                          const window::StageObserver& observer = {});
  // End of the input: a waiting initialisation decides on all it has (see the file comment);
  // the frames it settles are returned (status kFailed with a message when it cannot start).
  VioFrameResult Finish(const window::StageObserver& observer = {});

  // Called for each frame once the window has its pose (at the start for the buffered frames
  // with a pose, then for each frame the window runs on), with T_w_c = T_w_b T_b_c.
  void SetFrameObserver(FrameObserver observer);

  bool initialized() const;
  const VioInitialization& initialization() const;
  // AddImage's undistortion into the pinhole of the observations (nullptr before the first
  // image) and that pinhole (calibration.camera.K for AddFrame).
  const vision::Undistorter* undistorter() const;
  const PinholeIntrinsics& K() const;
  // Every frame given so far, with the refined (backfilled) poses; frames still buffered for
  // the initialisation have none.
  const std::vector<VioFrameRecord>& RefinedTrajectory() const;
  // The counts of the frames settled so far (IMU-only stretches among them).
  const VioStatistics& statistics() const;
  // The extrinsic the window uses (calibration.T_b_c before the start) and whether it is free.
  SE3d ExtrinsicEstimate() const;
  bool ExtrinsicFree() const;
  // The camera-IMU time offset the window uses now (s, t_imu = t_cam + td): the option's value, or
  // its estimate with estimate_time_offset once the window has started.
  double TimeOffsetEstimate() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// What each trajectory holds, one line each (the comments of `plucker vio`'s TUM files).
extern const char* const kRefinedTrajectoryNote;
extern const char* const kOnlineTrajectoryNote;

// The window's options for these options and sensors (also the dynamic start's vision-only
// window, with the inertial part removed).
window::SlidingWindowOptions WindowOptions(const VisualInertialOdometryOptions& options,
                                           const VisualInertialCalibration& calibration);
vision::ImageFrontendOptions FrontendOptions(const VisualInertialOdometryOptions& options);

}  // namespace odometry
}  // namespace plucker
