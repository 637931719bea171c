// Keyframe sliding-window estimator over camera poses, 3D points and orthonormal lines, with the
// oldest keyframe marginalized into a linear prior (the VINS-Mono pattern without the IMU;
// docs/vo.md). No I/O, no printing, no timing: the caller times AddFrame.
//
// The algorithm, per frame (AddFrame):
//   predict   the pose: the caller's guess, else constant velocity from the last two frames;
//   track     motion-only refinement of that pose against the window's landmarks (robust loss),
//             observations with large residuals flagged as outliers for this frame;
//   decide    keyframe: rotation-compensated median parallax of the points against the newest
//             keyframe, or too few tracked landmarks (in number or as a share of the frame's
//             observations);
//   non-keyframe: the tracked pose is the result and the frame is dropped (its observations are
//             discarded, as VINS-Mono does with the second-newest frame when it is no keyframe);
//   keyframe: the frame joins the window, new points and lines are triangulated from the
//             window's keyframes (linear N-view, parallax and conditioning checks), the window is
//             solved (Ceres, analytic factors, robust loss, the prior), outliers are culled, and
//             when the window holds more than window_size keyframes the oldest is marginalized.
//
// State:
//   poses   T_w_c per keyframe, 7-value blocks with PoseManifold.
//   points  3D in the world (3-vector blocks, the verified PointReprojectionFactor). Inverse depth
//           in an anchor keyframe conditions far points better, but it needs its own factor (and
//           its proofs) and re-anchoring when the anchor is marginalized; here a point is created
//           only with enough parallax (PointTriangulationOptions::min_parallax_deg) so that its
//           3D position is well determined, and marginalizing its first observer leaves it as it
//           is.
//   lines   orthonormal blocks (LineManifold) in a per-line anchor frame (anchored_line_factor.h:
//           scene-scale normalisation, so that far lines converge as fast as near ones).
//
// Marginalization (oldest keyframe k0): the residuals touching k0 (its point and line
// observations, its pose prior, the previous prior) are linearised and the Schur complement
// removes k0 and every landmark that no remaining keyframe observes; landmarks still observed keep
// the information of k0's observations in the prior, except k0's observations of lines that stay:
// those stay as they are, with k0's pose retained in the state until the lines leave
// (retain_line_observer_poses, by default no line is then ever a block of the prior;
// `keep_marginalized_lines = false` drops k0's line observations instead, what PL-VIO does).
// First-estimate Jacobians: every factor touching a block of the prior evaluates its Jacobian at
// the prior's linearisation point of that block (the residual at the current value), and a block
// already in the prior enters the next marginalization at that same point, so the prior does not
// gain information along the unobservable directions (gauge and scale) by relinearisation.
//
// Gauge: until the first marginalization the oldest keyframe is held constant; the scale is that
// of the initialisation (monocular: arbitrary, kept consistent by the window).
//
// Visual-inertial mode (SlidingWindowOptions::inertial, docs/vio.md): the pose blocks hold the
// body pose T_w_b in a gravity-aligned world and every keyframe has a velocity v_w (3) and a bias
// block [b_g, b_a] (6). The visual factors see the camera through the extrinsic T_b_c
// (PointReprojectionFactorVI, AnchoredLineFactorVI with the extrinsic held, or, with
// InertialOptions::estimate_extrinsic once it is free, on one extrinsic pose block with a prior
// from the given T_b_c, kept in the marginalization prior like a pose); an ImuFactor joins
// consecutive keyframes (preintegrated keyframe to keyframe from the samples given to AddImu,
// integrated again when a bias moves far from its linearisation point). A frame's pose is
// predicted by the IMU from the newest keyframe's state and then tracked visually; when too
// little is tracked the IMU prediction is the result. A keyframe is also taken when
// InertialOptions::max_imu_factor_span_s has passed (the IMU factors stay short, a standing body
// keeps its window). Marginalizing the oldest keyframe puts its IMU factor to the successor, its
// priors and its visual observations into the prior (FEJ as above). Gauge: position and yaw
// (4-DoF); until the first marginalization the oldest pose is held. The first keyframe carries
// priors on its biases and velocity from the initialisation.
//
// Code layout: this header is the whole public API; the implementation is split by
// responsibility over the window_*.cc files and the two marginalization strategies, mapped in
// window_internal.h (docs/vo.md, "Code layout").
#pragma once

#include <Eigen/Core>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "plucker/factors/anchored_line_factor.h"
#include "plucker/factors/imu_preintegration.h"
#include "plucker/factors/marginalization.h"
#include "plucker/factors/robust_loss.h"
#include "plucker/geometry/camera.h"
#include "plucker/geometry/line_triangulation.h"
#include "plucker/geometry/point_triangulation.h"
#include "plucker/geometry/se3.h"
#include "plucker/sensor/body_state.h"
#include "plucker/sensor/camera_observations.h"
#include "plucker/sensor/imu.h"

namespace plucker {
namespace window {

// The visual-inertial mode (see the file comment).
struct InertialOptions {
  SE3d T_b_c;  // camera in the body (IMU) frame: held fixed, or the start of its estimate
  // Online estimation of T_b_c (docs/vio.md, "Online extrinsic estimation"): one extrinsic pose
  // block in the window, on which the visual factors act directly, with a prior from T_b_c and
  // the sigmas below (PoseManifold tangent: rotation, then translation), kept in the
  // marginalization prior like a pose. false: T_b_c held fixed (the behaviour before the option).
  bool estimate_extrinsic = false;
  double extrinsic_rotation_sigma = 0.05;     // rad (2.9 deg)
  double extrinsic_translation_sigma = 0.02;  // m
  // Held at T_b_c until the window's keyframes have rotated about two axes: the second singular
  // value of their rotation vectors relative to the oldest keyframe reaches this (deg), then free
  // for good. 0 (default): free from the start; the prior keeps the unobservable directions where
  // it says. Holding first is worse: the marginalization prior built meanwhile holds pose
  // information conditioned on the held value (docs/vio.md: room, 3 deg, ATE 0.072 m against
  // 0.026 m free from the start and 0.054 m held).
  double extrinsic_min_rotation_deg = 0.0;
  // Online estimation of the camera-IMU time offset td (docs/math/time-offset.md), in Kalibr's
  // convention t_imu = t_cam + td (IMU stamps that run 8 ms late: td = +0.008): one scalar block
  // in the window, kept in the marginalization prior like the extrinsic, with a prior from
  // time_offset_s of time_offset_prior_sigma_s; the visual factors move each observation along its
  // image velocity (uv - td v: factors/time_offset_factor.h). The velocity is the observation's
  // (sensor::PointObservation::uv_velocity, SegmentObservation::s_/e_velocity) or, when the caller
  // gives none, computed by the window from the track's two previous observations in the frames
  // given to it (zero before that), and for a keyframe replaced, when the next frame arrives, by
  // the central difference of its neighbours: a velocity computed with the observation itself
  // shares its noise and biases td (window_time_offset.cc). Tracking sees the observations moved by
  // the current estimate. false (default): no block, no velocities, everything as before the
  // option.
  bool estimate_time_offset = false;
  // With estimate_time_offset: before each window solve, the image velocities the window fills in
  // for the keyframes' observations of existing landmarks are replaced by the motion predicted
  // from the keyframe's state, d/dt pi(T_c_w(t) x_w) with the body velocity, the gyroscope minus
  // its bias and the landmark (a segment's endpoint: the point of its line nearest to the
  // endpoint's ray). They carry no pixel noise: differenced velocities do, and, td being nearly
  // collinear with a shift of the poses, that noise dilutes the estimate (the room, +8 ms:
  // 5.62 ms recovered with them). false: the differenced velocities only.
  bool time_offset_velocity_from_state = true;
  double time_offset_s = 0.0;               // the initial value (and the prior's mean)
  double time_offset_prior_sigma_s = 0.02;  // s
  sensor::ImuModel imu;
  Eigen::Vector3d gravity_w{0.0, 0.0, -9.81};  // the world is gravity-aligned
  // Priors on the first keyframe's state at initialisation (standard deviations).
  double gyro_bias_prior_sigma = 0.01;  // rad/s
  double accel_bias_prior_sigma = 0.1;  // m/s^2
  double velocity_prior_sigma = 0.1;    // m/s
  // Before the first marginalization (no prior yet) the oldest keyframe holds the gauge: its whole
  // pose (false, default), or only its position and yaw (true: its roll and pitch, observable
  // through gravity, are solved for; factors/pose_manifold.h RollPitchPoseManifold). The
  // visual-inertial bundle adjustment of the dynamic start (odometry/visual_inertial_start_ba.h)
  // sets it to correct the alignment's gravity direction.
  bool free_first_tilt = false;
  // An IMU factor is integrated again when the bias at its start moved further than this from
  // its linearisation point.
  double repropagate_gyro_bias = 2e-3;   // rad/s
  double repropagate_accel_bias = 0.05;  // m/s^2
  // A keyframe at the latest this long after the previous one, tracked or not (the IMU factors
  // stay short). SlidingWindowOptions::max_keyframe_interval_s is the visual policy.
  double max_imu_factor_span_s = 1.0;
  // A frame the caller marks stationary (FrameInput::stationary: no image motion) keeps the
  // newest keyframe's pose instead of the IMU prediction, and as a keyframe gets a zero-motion
  // factor to the previous keyframe (same pose, zero velocity) with these standard deviations:
  // without it a standing body's pose is the double integral of the vibration.
  double stationary_position_sigma = 1e-3;  // m
  double stationary_rotation_sigma = 1e-4;  // rad
  double stationary_velocity_sigma = 1e-2;  // m/s
  // The caller's flag is believed only while the newest keyframe's speed and the speed the IMU
  // predicts for the frame are both below this: under forward motion most points lie far ahead
  // and barely move in the image (the simulated corridor at 0.3-1 m/s: a median displacement
  // under 3 px in 50 of 600 frames), which an image test alone takes for standing still. The
  // prediction matters after a standing start: the keyframes at rest have zero speed, and a body
  // speeding up forward at 20 Hz kept looking still, its velocity clamped to zero by the
  // zero-motion updates, the IMU prediction corrupted and nothing triangulated (issue 26 2b).
  double stationary_max_speed = 0.05;  // m/s
  // ... and the IMU's predicted speed below this (m/s): looser, as the prediction from a keyframe
  // at rest carries the static start's accelerometer bias error over up to a second.
  double stationary_max_predicted_speed = 0.2;
  // A step between IMU samples longer than this (s) is a gap. The prediction's speed across one is
  // not evidence (the readings are interpolated between its two ends: rotor vibration at rest in
  // the two samples around a 0.21 s gap of the EuRoC V1_01 head makes 0.27 m/s), so the speed test
  // above takes the prediction up to the gap's start.
  double imu_gap_s = 0.05;
  // Per-frame tracking fuses the IMU prediction from the newest keyframe: a prior on the body
  // pose with the preintegration's covariance plus this velocity uncertainty of the keyframe
  // (m/s per axis) times the time since it (and, with estimate_extrinsic, the extrinsic prior's
  // sigmas: the tracking sees the camera through the held estimate). 0: vision-only tracking
  // (the behaviour before).
  // Why (docs/vio.md, "Tracking with the IMU prediction"): on the 120 s room the prediction is
  // 3-9x closer to the truth than the vision-only pose, relative to the keyframe it starts from.
  double tracking_velocity_sigma = 0.02;
};

struct SlidingWindowOptions {
  int window_size = 10;  // keyframes kept in the window (>= 2)
  // Keyframe policy: rotation-compensated median point parallax against the newest keyframe
  // (px; with fewer than 8 common points, focal * baseline / median landmark depth), or fewer
  // tracked landmarks (points + lines) than min_tracked, or than min_tracked_ratio of the frame's
  // observations (the view has moved on to new structure).
  double keyframe_parallax_px = 10.0;
  int min_tracked = 20;
  double min_tracked_ratio = 0.6;
  // The observations min_tracked_ratio is a share of: the frame's points and, with this, only its
  // segments of mapped lines (those it can track; a point track counts whether mapped or not, but
  // most segments of an image front end never become lines: the MH_05 clip's 60 segments a frame
  // against 0-2 lines in the window). false: all its segments, so that with lines the 200 points
  // and 60 segments of an image need 52 tracked landmarks instead of 40, and keyframes come at
  // other frames than without lines.
  bool tracked_ratio_mapped_segments = false;
  // Also a keyframe when this much time has passed since the newest one (s; 0: off, the VO
  // default). The vision-only window of the dynamic VIO initialisation sets it so that the IMU
  // is preintegrated over short spans (the inertial mode has its own, InertialOptions).
  double max_keyframe_interval_s = 0.0;
  // Also a keyframe when the frame has turned this much from the newest keyframe (deg; 0: off, the
  // VO default): under fast turns the tracks end before the parallax builds up.
  double keyframe_max_rotation_deg = 0.0;
  // ... and only when some frame since the newest keyframe turned at this rate or faster from its
  // previous frame (deg/s; 0: at any rate). The normal simulated motions turn at up to 31 deg/s,
  // the aggressive corridor at up to 70 (the fast room 250), so a bound between applies the
  // rotation keyframes to fast turns only.
  double keyframe_min_turn_rate_deg_s = 0.0;
  // Robust loss on the reprojection residuals (pixels, whitened by the sigmas below).
  factors::RobustLoss loss = factors::RobustLoss::kHuber;
  double loss_scale = 1.5;  // in units of sigma
  double point_sigma_px = 1.0;
  double line_sigma_px = 1.0;
  double outlier_sigmas = 4.0;  // observations whose whitened residual norm exceeds this: culled
  // Iteration budget given by the caller (the library reads no clock).
  int max_iterations = 10;          // window solve
  int max_tracking_iterations = 8;  // motion-only pose refinement
  bool use_lines = true;
  bool keep_marginalized_lines = true;  // false: drop the marginalized keyframe's lines
  // k0's observations of the lines that stay in the window (kLandmarks prior, not in the
  // inertial mode): kept as they are with k0's pose, which stays in the state (a block of the
  // prior, first-estimate Jacobians like the others, without its keyframe) until those lines leave
  // or max_retained_poses is exceeded (true), or put in the prior at once (false). Lines are young
  // when k0 leaves: in the prior they then moved on average 0.14 rad (tangent) away from their
  // linearisation point (points: 2.5 % of their depth), so the prior's linear model of them
  // degraded over a run and kept lost to dropped; relinearising them instead made the prior
  // inconsistent (worse). Measured: docs/vo.md.
  bool retain_line_observer_poses = true;
  // At most this many retained poses; beyond, the oldest is marginalized. Its observations of the
  // lines that stay are then dropped (default), or with retained_overflow_into_prior they enter
  // the prior at the lines' estimates of that moment. So by default no line is ever a block of
  // the prior: a line in the prior has the Jacobians of all its later factors frozen at its
  // first estimate, and long-lived lines (the corridor's) kept moving away from it (0.12 rad
  // tangent on average, up to 2 rad, when they left), so that kept lost to dropped on 200-frame
  // corridors. Measured: docs/vo.md.
  int max_retained_poses = 10;
  bool retained_overflow_into_prior = false;
  bool first_estimate_jacobians = true;  // false: relinearise everything (VINS-Mono)
  // FEJ on the landmarks (points and lines) of the prior too: the prior lives on the landmarks k0
  // observed, the poses enter it only through them. Off, the prior gains spurious information
  // and points-only odometry diverges on the scarce-point room (ATE 1.9 m vs 0.06 m); relinearising
  // only the lines doubled the ATE of the lines-kept runs (0.094 vs 0.044 m, 2 seeds).
  bool first_estimate_landmarks = true;
  bool condition_far_lines = true;  // false: lines stored in the world frame
  // The prior's blocks. kLandmarks (default): the prior keeps k0's observations of the landmarks
  // that stay, so it lives on those landmarks: exact, but dense over hundreds of landmarks, which
  // makes every later window solve (Schur complement) and marginalization cost O(landmarks^3).
  // kPoses (the DSO pattern): a landmark observed by k0 whose track has ended (the newest
  // keyframe does not observe it) is marginalized with all its window observations, landmark by
  // landmark (a small Schur complement each), and retired (its track id is never triangulated
  // again); a landmark still tracked by the newest keyframe loses k0's observation. The prior
  // lives on poses only (at most 6 x window_size), and the window solve stays sparse. Inertial
  // mode: k0's pose, velocity and bias are eliminated with its state priors and its IMU factor
  // to the successor, whose velocity and bias blocks join the prior (nothing inertial dropped).
  enum class PriorBlocks { kLandmarks, kPoses };
  PriorBlocks prior_blocks = PriorBlocks::kLandmarks;
  // kPoses: a track whose landmark went into the prior is retired (true; image tracks end for
  // good), or only its window observations are marked used, so that the same id can start a new
  // landmark from later keyframes (false; features folders whose ids are scene ids, revisited:
  // retiring them starved the 60 s room of points after 16 s).
  bool retire_marginalized_tracks = true;
  // When motion-only tracking fails (too few inliers from the prediction, e.g. after a jump):
  // PnP RANSAC (OpenCV EPnP) of the frame's point tracks against the window's 3D points, then
  // tracking again from that pose.
  // Until the first marginalization only the oldest keyframe holds the gauge, and the scale is
  // free: with a start on a short baseline it wandered by +-10 % from solve to solve on the MH_05
  // take-off, and the first prior froze it (docs/vo.md, "Scale drift on MH_05"). With this
  // (> 0), the distance between the two oldest keyframes is held at its value after the start by
  // a prior of this relative standard deviation until the first prior exists. 0 (default): off.
  // Not in the inertial mode (gravity and the IMU hold the scale there).
  double start_scale_sigma = 0.0;
  bool pnp_fallback = true;
  double pnp_threshold_px = 3.0;  // RANSAC inlier threshold
  int pnp_min_inliers = 10;
  PointTriangulationOptions point_triangulation;
  // New lines need 5 deg between back-projected planes (2 deg let lines nearly parallel to the
  // motion in: the corridor's ATE went from 0.43 m to 0.13 m with 5).
  LineTriangulationOptions line_triangulation = [] {
    LineTriangulationOptions o;
    o.min_plane_angle_deg = 5.0;
    return o;
  }();
  double max_line_sigma_ratio = 0.2;  // reject ill-conditioned N-view lines (sigma3 / sigma2)
  // A new line also needs this many keyframes observing it (>= 2), and the RMS endpoint-to-line
  // distance of its triangulation in those views at most max_new_line_rms_px (0: no test).
  int min_line_views = 2;
  double max_new_line_rms_px = 0.0;
  // A line triangulated from two views is exactly determined (two back-projected planes always
  // meet): its observations are weighed with line_sigma_px times this until a third view
  // observes its track (1: off, the default). Unlike min_line_views 3, the line is in at once.
  double two_view_line_sigma_scale = 1.0;
  // A line made from two views is triangulated again, with the checks above, when a third
  // keyframe observes its track: replaced by that estimate, or dropped if a check fails (false:
  // kept as it is, the default). The window then holds the lines min_line_views 3 would make,
  // and the two-view lines meanwhile (tracking).
  bool recheck_two_view_lines = false;
  // A line made from two views also needs the largest angle between its back-projected planes to
  // be at least this many pixels' angles (atan(px / f), f the mean focal length; 0: off, the
  // default): an exactly determined line's depth error grows as the pixel's angle over the
  // plane angle, so the test asks the same conditioning of every camera (the 5 deg of
  // line_triangulation are 35 px at f = 400, 17 px on the fisheye's view at f = 189). A line
  // refused here is tried again, with the 5 deg, once a third keyframe sees it.
  double two_view_min_plane_angle_px = 0.0;
  MarginalizationOptions marginalization;
  std::optional<InertialOptions> inertial;  // set: visual-inertial mode
  // Stereo mode (docs/vo.md, "Stereo"): the second camera (same K) at T_c0_c1 in the frame of
  // the camera whose poses the window estimates. Its observations (FrameInput::right_points,
  // right_segments: the left's track ids) are triangulated with the left's (a landmark from one
  // keyframe's left-right pair, metric) and enter the window and the marginalization as the
  // verified VI factors with the extrinsic held at T_c0_c1 (PointReprojectionFactorVI,
  // AnchoredLineFactorVI through HeldExtrinsicFactor); a right observation is used only with an
  // inlier left observation of its track in the same frame, and culled with it. Tracking uses the
  // left observations only. Not with the inertial mode (the constructor throws).
  std::optional<SE3d> T_c0_c1;
};

// One frame's input: the observations with their track ids (sensor/camera_observations.h, from
// the simulator, a features folder or an image front end alike; `frame` fields are ignored) and
// optional pose information (the hooks for the IMU: a prediction and a prior).
struct FrameInput {
  double time = 0.0;
  std::vector<sensor::PointObservation> points;
  std::vector<sensor::SegmentObservation> segments;
  std::optional<SE3d> T_w_c_guess;  // prediction (else constant velocity)
  // Prior r = sqrt_information * Minus(T_w_c, prior) (PoseManifold tangent: rotation, then
  // translation), kept while the frame is in the window and marginalized with it.
  std::optional<SE3d> T_w_c_prior;
  Eigen::Matrix<double, 6, 6> prior_sqrt_information = Eigen::Matrix<double, 6, 6>::Identity();
  bool stationary = false;  // inertial mode: the caller saw no image motion (see InertialOptions)
  // Stereo mode (SlidingWindowOptions::T_c0_c1): the second camera's observations, with the
  // track ids of the matching left observations; ignored otherwise.
  std::vector<sensor::PointObservation> right_points;
  std::vector<sensor::SegmentObservation> right_segments;
};

struct WindowFrameResult {
  bool ok = false;            // false: too little to track; T_w_c is the prediction
  bool pnp_fallback = false;  // tracking from the prediction failed and PnP RANSAC was tried
  SE3d T_w_c;
  bool keyframe = false;
  int tracked_points = 0;  // observations of existing landmarks kept as inliers
  int tracked_lines = 0;
  int new_points = 0;  // landmarks triangulated at this frame
  int new_lines = 0;
  int window_points = 0;  // landmarks in the window after the frame
  int window_lines = 0;
  int window_keyframes = 0;
  int tracking_iterations = 0;
  int window_iterations = 0;
  double initial_cost = 0.0;  // window solve (Ceres cost, 1/2 sum of squares)
  double final_cost = 0.0;
  int residuals = 0;  // residual blocks in the window solve
  int culled_observations = 0;
  // The lines' share of the window solve (keyframes): their residual blocks, the culled ones
  // among culled_observations, and the RMS whitened residual norm (sigmas) after the solve of the
  // line and of the point observations kept.
  int line_residuals = 0;
  int culled_line_observations = 0;
  double line_rms_sigmas = 0.0;
  double point_rms_sigmas = 0.0;
  // New lines (keyframes): the newest keyframe's segment tracks without a line seen by >= 2
  // keyframes (triangulation tried), and those rejected for too small an angle between the
  // back-projected planes (LineTriangulationOptions::min_plane_angle_deg) or for conditioning
  // (max_line_sigma_ratio) or another reason (behind the camera, degenerate, max_new_line_rms_px).
  int line_candidates = 0;
  int line_small_parallax = 0;
  int line_ill_conditioned = 0;
  int line_other_rejections = 0;
  // SlidingWindowOptions::recheck_two_view_lines: two-view lines dropped at their third view.
  int rechecked_lines_dropped = 0;
  int marginalized_keyframes = 0;  // 0 or 1
  int marginalized_landmarks = 0;
  int dropped_line_observations = 0;  // keep_marginalized_lines = false
  int held_line_observations = 0;     // k0's line observations kept at its pose (this frame)
  // Observations of a retained pose that left beyond max_retained_poses, of lines that stay:
  // dropped (retained_overflow_into_prior = false).
  int dropped_retained_line_observations = 0;
  int retained_poses = 0;  // marginalized keyframes' poses retained in the state, after the frame
  int prior_lines = 0;     // line blocks of the prior, after the frame
  int dropped_point_observations = 0;  // PriorBlocks::kPoses: k0's observations of live tracks
  int prior_rank = 0;
  int prior_dimension = 0;  // tangent dimension of the prior's blocks (after a marginalization)
  bool marginalization_failed = false;  // the prior was reset (Build threw)
  double parallax_px = 0.0;
  // Visual-inertial mode: the body state (a non-keyframe: the tracked pose with the IMU-predicted
  // velocity and the newest keyframe's bias), whether the pose is the IMU prediction alone
  // (too little tracked), and the whitened squared residual of the newest IMU factor after the
  // solve (15 degrees of freedom; 0 for a non-keyframe).
  sensor::BodyState state;
  bool imu_only = false;
  bool stationary = false;  // the caller's flag, believed (InertialOptions::stationary_max_speed)
  double imu_chi2 = 0.0;
  bool extrinsic_free = false;  // InertialOptions::estimate_extrinsic: T_b_c is being estimated
};

// The stages of AddFrame, announced as they start (kDone at the end) so that the caller can time
// them; the library reads no clock.
enum class WindowStage { kTracking, kTriangulation, kSolve, kMarginalization, kDone };
constexpr int kNumWindowStages = 4;
using StageObserver = std::function<void(WindowStage)>;

// The result of Initialize.
struct InitializationResult {
  bool ok = false;
  int points = 0;
  int lines = 0;
  int iterations = 0;
  double final_cost = 0.0;  // of the initial solve (Ceres cost, robust, whitened)
  int residuals = 0;        // its residual blocks
  SE3d T_w_a, T_w_b;        // after the initial solve
};

class SlidingWindowEstimator {
 public:
  SlidingWindowEstimator(const PinholeIntrinsics& K, const SlidingWindowOptions& options);
  ~SlidingWindowEstimator();
  SlidingWindowEstimator(const SlidingWindowEstimator&) = delete;
  SlidingWindowEstimator& operator=(const SlidingWindowEstimator&) = delete;

  // Starts the window with two keyframes at known poses (e.g. a two-view initialisation, up to
  // scale): triangulates their common tracks and solves with the first pose held. Fails (ok =
  // false, state cleared) with fewer than `min_landmarks` landmarks.
  InitializationResult Initialize(const FrameInput& a, const SE3d& T_w_a, const FrameInput& b,
                                  const SE3d& T_w_b, int min_landmarks = 10);
  // The same with N >= 2 keyframes (oldest first) at known poses, e.g. a two-view start and
  // frames between its views localised against it: the tracks of all triangulated, one solve of
  // all poses, points and lines (the first pose held). Throws std::invalid_argument when the
  // sizes differ, N < 2 or N > window_size, and std::logic_error in the inertial mode.
  InitializationResult Initialize(const std::vector<FrameInput>& frames,
                                  const std::vector<SE3d>& T_w_c, int min_landmarks = 10);
  // Stereo mode: starts the window with one keyframe at a known pose, its landmarks triangulated
  // from its left-right pairs (metric), solved with the pose held. Fails (ok = false, state
  // cleared) with fewer than `min_landmarks` landmarks. Throws std::logic_error outside the
  // stereo mode.
  InitializationResult InitializeStereo(const FrameInput& frame, const SE3d& T_w_c,
                                        int min_landmarks = 10);
  bool initialized() const;

  // Visual-inertial mode. AddImu appends IMU samples (times increasing across calls; throws
  // std::invalid_argument otherwise); they must cover a frame's time before AddFrame (else
  // AddFrame throws std::invalid_argument and changes nothing). InitializeInertial starts the
  // window with two keyframes at known body states (static or visual-inertial initialisation),
  // the IMU between them preintegrated; min_landmarks may be 0 (a standing body). Both throw
  // std::logic_error outside the inertial mode.
  void AddImu(const std::vector<sensor::ImuSample>& samples);
  InitializationResult InitializeInertial(const FrameInput& a, const sensor::BodyState& state_a,
                                          const FrameInput& b, const sensor::BodyState& state_b,
                                          int min_landmarks = 0);
  // The same with N >= 2 keyframes (oldest first; e.g. all those of a visual-inertial alignment):
  // IMU factors between consecutive ones, the landmarks of every keyframe triangulated. Throws
  // std::invalid_argument when the sizes differ or N < 2 (or N > window_size).
  InitializationResult InitializeInertial(const std::vector<FrameInput>& frames,
                                          const std::vector<sensor::BodyState>& states,
                                          int min_landmarks = 0);
  std::vector<sensor::BodyState> KeyframeStates() const;  // oldest first
  // The camera-body extrinsic T_b_c the window uses now: InertialOptions::T_b_c, or its estimate
  // (InertialOptions::estimate_extrinsic). Throws std::logic_error outside the inertial mode.
  SE3d ExtrinsicEstimate() const;
  bool ExtrinsicFree() const;  // estimated and no longer held (see InertialOptions)
  // The camera-IMU time offset td the window uses now (s, t_imu = t_cam + td):
  // InertialOptions::time_offset_s, or its estimate with estimate_time_offset. Throws
  // std::logic_error outside the inertial mode.
  double TimeOffsetEstimate() const;

  // Processes the next frame (after Initialize). See the file comment.
  WindowFrameResult AddFrame(const FrameInput& frame, const StageObserver& observer = {});

  // Motion-only pose of a frame against the current landmarks, from the guess; the state is not
  // changed (frames between the two initialisation views). nullopt if too little is tracked.
  std::optional<SE3d> Localize(const FrameInput& frame, const SE3d& guess) const;

  // Covariance of the newest keyframe's pose in its PoseManifold tangent (rotation, translation),
  // from the window's information at the current estimate (prior included). nullopt when it is
  // rank-deficient (no pose prior fixes the gauge) or not computable. Visual-inertial mode: of
  // T_w_b, with the gauge (position and yaw) held on the oldest keyframe, whose roll and pitch
  // (observable through gravity) stay free.
  std::optional<Eigen::Matrix<double, 6, 6>> NewestPoseCovariance() const;

  // The keyframes' poses (oldest first) and the landmarks (for drawing and tests).
  std::vector<SE3d> KeyframePoses() const;
  std::map<int, Eigen::Vector3d> Points() const;
  std::map<int, Line6d> Lines() const;  // world Plücker lines, |d| = 1

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace window
}  // namespace plucker
