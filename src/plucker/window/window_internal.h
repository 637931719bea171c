// Private to the window layer (not installed): the state of SlidingWindowEstimator (its Impl)
// and the map of where each responsibility lives. Every member function below is defined in the
// file named above its group; AddFrame (sliding_window_estimator.cc) calls them in the order of
// the algorithm in sliding_window_estimator.h: predict, track, decide, triangulate, solve,
// marginalize.
//
//   window_state.cc                  frames, landmarks, retained poses: creation, bookkeeping,
//                                    removal of weak landmarks, installing a new prior
//   window_residuals.cc              the residuals of the window and the Ceres problem built
//   window_inertial.cc               the IMU buffer, prediction, the inertial residuals, AddImu
//   window_extrinsic.cc              online estimation of T_b_c
//   window_time_offset.cc            online estimation of the camera-IMU time offset
//   window_tracking.cc               motion-only tracking of a frame, the PnP RANSAC fallback
//   window_keyframe_policy.cc        parallax and the keyframe decision
//   window_triangulation.cc          new points and lines from the window's keyframes
//   window_solve.cc                  the window solve and outlier culling
//   marginalization_strategy_internal.h, landmark_prior_marginalization.cc,
//   poses_only_marginalization.cc    the two ways to marginalize the oldest keyframe
//   window_initialization.cc         the four initialisation entry points
//   window_stereo.cc                 stereo mode: right observations, their residuals, the start
//   window_diagnostics.cc            per-frame counts, the IMU chi-square, the pose covariance
#pragma once

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/problem.h>

#include <deque>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <vector>

#include "plucker/factors/line_manifold.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/window/marginalization_strategy_internal.h"
#include "plucker/window/sliding_window_estimator.h"

namespace plucker {
namespace window {
namespace internal {

enum class BlockKind { kPose, kPoint, kLine, kVelocity, kBias, kTimeOffset };

struct Frame {
  FrameInput input;
  double pose[7];                     // T_w_c, or T_w_b in the inertial mode
  std::vector<char> point_outlier;    // per input.points
  std::vector<char> segment_outlier;  // per input.segments
  // Stereo mode: per input.points / input.segments, the index of the same track's observation in
  // input.right_points / right_segments, or -1.
  std::vector<int> right_point, right_segment;
  // With the time offset estimated: the observations whose image velocity the window filled in
  // (not given by the caller), per input.points / input.segments.
  std::vector<char> point_velocity_filled, segment_velocity_filled;
  // ... and the gyroscope reading at input.time (interpolated; none when the IMU does not cover
  // it), from which the keyframe's image velocities are predicted (PredictImageVelocities).
  std::optional<Eigen::Vector3d> gyro;
  // Inertial mode: the extrinsic, the velocity and bias blocks, the IMU from the previous
  // keyframe, and the priors of the first keyframe.
  std::optional<SE3d> T_b_c;
  double v[3] = {0.0, 0.0, 0.0};
  double bias[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};  // [b_g, b_a]
  std::unique_ptr<ImuPreintegration> imu_from_previous;
  bool state_prior = false;
  double v_prior[3], bias_prior[6];
  SE3d T_w_c() const {
    return T_b_c ? SE3d::FromParameters(pose) * *T_b_c : SE3d::FromParameters(pose);
  }
  void SetCameraPose(const SE3d& T_w_c) {
    (T_b_c ? T_w_c * T_b_c->Inverse() : T_w_c).ToParameters(pose);
  }
  sensor::ImuBias Bias() const {
    sensor::ImuBias b;
    b.gyro = Eigen::Vector3d(bias[0], bias[1], bias[2]);
    b.accel = Eigen::Vector3d(bias[3], bias[4], bias[5]);
    return b;
  }
  void SetState(const sensor::BodyState& s) {
    s.T_w_b.ToParameters(pose);
    for (int i = 0; i < 3; ++i) {
      v[i] = s.v_w(i);
      bias[i] = s.bias.gyro(i);
      bias[3 + i] = s.bias.accel(i);
    }
  }
  sensor::BodyState State() const {
    return {input.time, SE3d::FromParameters(pose), Eigen::Vector3d(v[0], v[1], v[2]), Bias()};
  }
};

struct PointLandmark {
  double p[3];
};

struct LineLandmark {
  LineAnchor anchor;
  double block[6];
  // Views of its track so far (at triangulation, then one more per keyframe observing it); below
  // three its observations are weighed with SlidingWindowOptions::two_view_line_sigma_scale.
  int views = 0;
};

// The pose of a marginalized keyframe kept in the state (a block of the prior, FEJ like the
// others) while lines that stay in the window have observations from it, and those observations.
struct RetainedPose {
  double pose[7];
  std::vector<sensor::SegmentObservation> segments;
};

// One residual of the window: its cost, whether the robust loss applies, and its blocks.
struct ResidualSpec {
  std::unique_ptr<ceres::CostFunction> cost;
  bool robust = true;
  std::vector<double*> blocks;
  // Where it came from (for culling): frame, observation index, point (true) or segment.
  Frame* frame = nullptr;
  int observation = -1;
  bool is_point = true;
  bool right = false;  // stereo: the second camera's observation of the left one `observation`
};

// Where an observation residual of the window problem came from (for culling).
struct ObservationBlock {
  ceres::ResidualBlockId id;
  Frame* frame;
  int observation;
  bool is_point;
};

// A frame's predicted pose and, in the inertial mode, its predicted state and the IMU
// preintegrated from the newest keyframe to it.
struct Prediction {
  SE3d T_w_c;
  sensor::BodyState state;
  std::unique_ptr<ImuPreintegration> imu;
  bool stationary = false;  // the caller's flag, believed
};

struct TrackResult {
  bool ok = false;
  SE3d T_w_c;
  int points = 0, lines = 0, iterations = 0;
};

}  // namespace internal

struct SlidingWindowEstimator::Impl {
  using Frame = internal::Frame;
  using ResidualSpec = internal::ResidualSpec;
  using BlockKind = internal::BlockKind;

  PinholeIntrinsics K;
  SlidingWindowOptions opt;
  std::deque<std::unique_ptr<Frame>> keyframes;  // oldest first
  std::map<int, std::unique_ptr<internal::PointLandmark>> points;
  std::map<int, std::unique_ptr<internal::LineLandmark>> lines;
  std::unique_ptr<MarginalizationPrior> prior;
  std::vector<double*> prior_blocks;                // the prior's kept blocks (real storage)
  std::map<const double*, std::vector<double>> fe;  // their first estimates
  std::unique_ptr<ceres::LossFunction> loss;
  PoseManifold pose_manifold;
  RollPitchPoseManifold roll_pitch_manifold;  // InertialOptions::free_first_tilt
  LineManifold line_manifold;
  // SlidingWindowOptions::prior_blocks: how the oldest keyframe leaves the window.
  std::unique_ptr<internal::MarginalizationStrategy> marginalization;
  SE3d last_T_w_c, prev_T_w_c;
  double last_time = 0.0;  // last_T_w_c's frame time
  // The fastest frame-to-frame turn since the newest keyframe (deg/s; the rotation keyframe's
  // keyframe_min_turn_rate_deg_s).
  double peak_turn_rate_deg_s = 0.0;
  // SlidingWindowOptions::start_scale_sigma: the distance held (0: not yet taken).
  double start_distance = 0.0;
  // Tracks whose landmark went into a poses-only prior: never triangulated again.
  std::set<int> retired_points, retired_lines;
  std::vector<std::unique_ptr<internal::RetainedPose>> retained;  // oldest first
  int prior_lines = 0;                                            // line blocks of the prior
  std::vector<sensor::ImuSample> imu;  // inertial mode: from just before the newest keyframe
  // Inertial mode: the extrinsic the window uses now (InertialOptions::T_b_c unless estimated),
  // its parameter block and its prior (InertialOptions::estimate_extrinsic).
  SE3d T_b_c;
  double extrinsic[7];
  bool extrinsic_free = false;
  std::unique_ptr<MarginalizationPrior> extrinsic_prior;
  // Inertial mode: the camera-IMU time offset (its block; InertialOptions::estimate_time_offset)
  // and, by track id, the previous frame's observation (time, the uv or the segment's endpoints a,
  // b, and the difference velocities ending there), from which the image velocities the caller
  // did not give are computed (window_time_offset.cc).
  double time_offset[1] = {0.0};
  struct LastObservation {
    double time;
    Eigen::Vector2d a, b, va, vb;
    // The track's observation in the frame before (a, b in the same order), at prev_time; NaN
    // without one.
    double prev_time = std::numeric_limits<double>::quiet_NaN();
    Eigen::Vector2d prev_a = Eigen::Vector2d::Zero(), prev_b = Eigen::Vector2d::Zero();
  };
  std::map<int, LastObservation> last_points, last_segments;
  // Whether the segment (s, e) matches the previous one with its endpoints swapped.
  static bool Swapped(const Eigen::Vector2d& s, const Eigen::Vector2d& e, const LastObservation& o);
  bool TimeOffsetOn() const { return opt.inertial && opt.inertial->estimate_time_offset; }
  // The gyroscope reading at time t, interpolated in the IMU buffer (none outside it).
  std::optional<Eigen::Vector3d> GyroAt(double t) const;
  // Before a window solve (time_offset_velocity_from_state): the image velocities the window
  // filled in for the keyframes' observations of existing landmarks, replaced by those predicted
  // from the keyframe's state (velocity, gyroscope minus bias, extrinsic) and the landmark.
  void PredictImageVelocities();

  // --- window_state.cc: bookkeeping ----------------------------------------------------------
  // With the time offset estimated, also fills in the image velocities (FillVelocities; the
  // callers that keep the frame then call RememberObservations).
  std::unique_ptr<Frame> MakeFrame(const FrameInput& input, const SE3d& T_w_c) const;
  void Clear();
  bool InPrior(const double* block) const;
  BlockKind KindOf(const double* block) const;
  const ceres::Manifold* ManifoldOf(BlockKind kind) const;
  static int AmbientSize(BlockKind kind);
  // Landmarks observed (as inliers) by fewer than two keyframes and not in the prior.
  void RemoveWeakLandmarks();
  // Drops the retained observations whose line is gone (or, with `cull`, whose residual exceeds
  // the outlier threshold), then the retained poses left with none that are not in the prior
  // (those in it leave at the next marginalization). Returns the observations culled.
  int PruneRetained(bool cull);
  // The new prior and its first estimates (none if empty).
  void InstallPrior(std::unique_ptr<MarginalizationPrior> next,
                    const std::vector<double*>& next_blocks, WindowFrameResult* result);
  // After k0 went into the prior: drop it and the landmarks eliminated with it.
  void DropOldestKeyframe(const std::vector<int>& remove_points,
                          const std::vector<int>& remove_lines, WindowFrameResult* result);

  // --- window_residuals.cc: residuals and the problem ----------------------------------------
  Eigen::Matrix2d PointSqrtInfo(const sensor::PointObservation& p) const {
    const Eigen::Matrix2d uniform = Eigen::Matrix2d::Identity() / opt.point_sigma_px;
    return p.sqrt_info_scale ? Eigen::Matrix2d(*p.sqrt_info_scale * uniform) : uniform;
  }
  // A line seen in two views only (exactly determined): sigma x two_view_line_sigma_scale.
  Eigen::Matrix2d LineSqrtInfo(const internal::LineLandmark& l) const {
    const double scale = l.views < 3 ? opt.two_view_line_sigma_scale : 1.0;
    return Eigen::Matrix2d::Identity() / (opt.line_sigma_px * scale);
  }
  // The visual costs on (pose, landmark): with the time offset, the observation moved by the
  // current estimate, held (tracking, culling); UseExtrinsicBlock frees td in the window.
  ceres::CostFunction* PointCost(const sensor::PointObservation& p) const;
  ceres::CostFunction* LineCost(const sensor::SegmentObservation& s,
                                const internal::LineLandmark& l) const;
  void AppendFrameResiduals(Frame* f, bool with_points, bool with_lines,
                            std::vector<ResidualSpec>* out) const;
  // The observations of the retained poses whose line exists (and, when `only` is given, is in
  // it), as residuals on (retained pose, line).
  void AppendRetainedResiduals(std::vector<ResidualSpec>* out, const std::set<int>* only = nullptr,
                               const internal::RetainedPose* from = nullptr) const;
  std::vector<const double*> FirstEstimatesOf(const std::vector<double*>& blocks) const;
  bool HasPosePrior() const;
  // Builds the window problem into `problem` (culling what cannot be evaluated first). Returns
  // the number of residual blocks; `observations` (optional): the keyframes' observation blocks.
  int BuildProblem(ceres::Problem* problem, bool hold_gauge,
                   std::vector<internal::ObservationBlock>* observations = nullptr);
  static ceres::Problem::Options ProblemOptions();

  // --- window_inertial.cc: the IMU ------------------------------------------------------------
  // The IMU from time t0 to t1 at the bias `bias` (throws std::invalid_argument when the samples
  // do not cover the interval).
  ImuPreintegration Preintegrate(double t0, double t1, const sensor::ImuBias& bias) const;
  // The state at time t predicted from the newest keyframe, with the preintegration used.
  sensor::BodyState Predict(double t, std::unique_ptr<ImuPreintegration>* preintegration) const;
  // The IMU factor between keyframes k - 1 and k, and the priors of keyframe k.
  void AppendInertialResiduals(std::size_t k, std::vector<ResidualSpec>* out) const;
  // Integrates the IMU factors again whose start bias moved far from the linearisation point.
  void RepropagateImu();
  // The time of the first IMU sample in [t0, t1) followed by a step longer than
  // InertialOptions::imu_gap_s (none without a gap).
  std::optional<double> ImuGapStart(double t0, double t1) const;
  // Drops the IMU samples before the newest keyframe (one sample before it is kept).
  void PruneImu();
  // The caller's stationary flag, believed only while the body moves slower than
  // InertialOptions::stationary_max_speed (an image test alone takes forward motion for standing).
  bool BelievedStationary(bool flag, const Eigen::Vector3d& v_w) const;
  // The prior the IMU prediction puts on a frame's body pose T_w_b (see the definition).
  ceres::CostFunction* ImuPosePrior(const sensor::BodyState& predicted,
                                    const ImuPreintegration& preintegration) const;

  // --- window_extrinsic.cc: InertialOptions::estimate_extrinsic -----------------------------
  void ResetExtrinsic();
  double RotationSpanDeg() const;
  void UpdateExtrinsicFree();
  void SyncExtrinsic();
  // With the extrinsic free and / or the time offset estimated, the visual residuals on
  // (pose, landmark) become the factors on (pose, [extrinsic], [td], landmark): the landmark
  // stays the last block.
  void UseExtrinsicBlock(std::vector<ResidualSpec>* residuals);

  // --- window_time_offset.cc: InertialOptions::estimate_time_offset --------------------------
  void ResetTimeOffset();
  // The image velocities the caller did not give, from the previous frame's observations
  // (flagged in the frame's *_velocity_filled).
  void FillVelocities(Frame* frame) const;
  // When the newest keyframe is the frame before `input`: the velocities it was given by
  // FillVelocities become central differences over its neighbours, (x_k+1 - x_k-1) /
  // (t_k+1 - t_k-1), which neither lag nor carry the observation's own noise.
  void RefineNewestKeyframeVelocities(const FrameInput& input);
  // The frame's observations become the previous frame's (with the time offset estimated).
  void RememberObservations(const FrameInput& input);
  // The prior r = (td - time_offset_s) / time_offset_prior_sigma_s.
  ceres::CostFunction* TimeOffsetPrior() const;

  // --- window_stereo.cc: SlidingWindowOptions::T_c0_c1 ---------------------------------------
  // The frame's valid right observations of the tracks it observes on the left, and the index
  // maps (Frame::right_point, right_segment).
  void AttachRight(Frame* f, const FrameInput& input) const;
  // The right camera's pose of a keyframe (stereo mode).
  SE3d RightPose(const Frame& f) const { return f.T_w_c() * *opt.T_c0_c1; }
  // The right observations of the left inliers whose landmark exists, on (pose, landmark).
  void AppendRightResiduals(Frame* f, bool with_points, bool with_lines,
                            std::vector<ResidualSpec>* out) const;

  // --- window_tracking.cc: predict and track --------------------------------------------------
  // The pose (and, inertial, state) of the next frame: the caller's guess, the IMU from the
  // newest keyframe, or constant velocity. Throws before any change when the IMU samples do not
  // cover the frame.
  internal::Prediction PredictFrame(const FrameInput& input) const;
  // `prior` (optional): a pose-only term on the frame's pose block (ImuPosePrior).
  internal::TrackResult Track(Frame* f, const SE3d& guess,
                              const ceres::CostFunction* prior = nullptr) const;
  // Track from the prediction (with the IMU prior when configured), then, when that fails and
  // pnp_fallback is on, from the PnP RANSAC pose (`*pnp_tried` set).
  internal::TrackResult TrackFrame(Frame* f, const FrameInput& input,
                                   const internal::Prediction& prediction, bool* pnp_tried) const;
  // The pose from PnP RANSAC of the frame's point tracks against the window's points, or nullopt.
  std::optional<SE3d> PnpPose(const Frame& f) const;
  void HoldStartScale(ceres::Problem* problem);

  // --- window_keyframe_policy.cc: decide ------------------------------------------------------
  double Parallax(const Frame& f) const;
  void UpdateTurnRate(const Frame& f);
  bool Turned(const Frame& f) const;
  int TrackableSegments(const Frame& f) const;
  // Sets result->parallax_px and returns whether the tracked frame becomes a keyframe.
  bool DecideKeyframe(const Frame& f, const internal::TrackResult& track,
                      WindowFrameResult* result) const;

  // --- window_triangulation.cc ----------------------------------------------------------------
  // New landmarks for the tracks of keyframe `f` (the newest) that have none yet.
  bool LineFits(const std::vector<LineObservation>& views, const Line6d& L_w) const;
  // `stats` (optional): the line_candidates and rejection counts.
  void Triangulate(const Frame& f, int* new_points, int* new_lines,
                   WindowFrameResult* stats = nullptr);
  // The new keyframe `f`'s inlier observations of existing lines: LineLandmark::views + 1 (and
  // SlidingWindowOptions::recheck_two_view_lines).
  void CountLineViews(const Frame& f, WindowFrameResult* stats);
  std::vector<LineObservation> LineViews(int id) const;
  // A line for track `id` from at least `min_views` views, with the new-line checks (nullptr:
  // fewer views or a check failed); counts into `stats`.
  std::unique_ptr<internal::LineLandmark> NewLine(int id, int min_views,
                                                  WindowFrameResult* stats) const;

  // --- window_solve.cc: solve and cull --------------------------------------------------------
  void SolveWindow(WindowFrameResult* result);
  // Marks the observations whose residual in `problem` (at the current values) cannot be
  // evaluated or exceeds the outlier threshold; returns the number marked.
  // `stats` (optional): the line/point split of the residuals and of the culled observations.
  int CullOutliers(const ceres::Problem& problem,
                   const std::vector<internal::ObservationBlock>& observations,
                   WindowFrameResult* stats = nullptr) const;

  // --- window_initialization.cc ---------------------------------------------------------------
  // The tail of every initialisation: the keyframes are in place.
  InitializationResult StartWindow(int min_landmarks);

  // --- window_diagnostics.cc ------------------------------------------------------------------
  // Whitened squared residual of the IMU factor into the newest keyframe (0 if none).
  double NewestImuChi2() const;
  void FillCounts(WindowFrameResult* r) const;
};

}  // namespace window
}  // namespace plucker
