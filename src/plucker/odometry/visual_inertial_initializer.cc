#include "plucker/odometry/visual_inertial_initializer.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "plucker/factors/imu_preintegration.h"
#include "plucker/geometry/median.h"
#include "plucker/inertial/initialization_choice.h"
#include "plucker/inertial/visual_inertial_alignment.h"
#include "plucker/window/two_view_initialization.h"

namespace plucker {
namespace odometry {
namespace {

bool Covered(const std::vector<sensor::ImuSample>& imu, double t) {
  return !imu.empty() && imu.front().t <= t && imu.back().t >= t;
}

// The metric pose of frame f from the visual pose, the alignment and keyframe 0's body pose.
SE3d AlignedBodyPose(const SE3d& T_vo_c0, const SE3d& T_vo_cf, double scale, const SE3d& T_w_b0,
                     const SE3d& T_b_c) {
  const SE3d rel = T_vo_c0.Inverse() * T_vo_cf;
  const SE3d scaled(rel.rotation(), scale * rel.translation());
  return T_w_b0 * T_b_c * scaled * T_b_c.Inverse();
}

// Whether the still test found the start of the motion (else the log ended while still).
bool MotionFound(const inertial::StaticInitResult& r, double block_seconds) {
  if (r.status == inertial::StaticInitStatus::kTooFewSamples) return false;
  const long used = std::lround((r.still_end - r.still_begin) / block_seconds);
  return r.blocks_still == 0 || used == r.blocks_still - 1;
}

// The pair's parallax before any RANSAC: the upper median, over the point tracks common to a and
// b, of the pixel distance between b's observation and a's ray turned into b by R_b_a (the
// gyroscope's rotation); 0 with fewer than 5 common tracks.
double RotatedParallax(const PinholeIntrinsics& K, const std::vector<sensor::PointObservation>& a,
                       const std::vector<sensor::PointObservation>& b,
                       const Eigen::Matrix3d& R_b_a) {
  std::map<int, Eigen::Vector2d> uv_a;
  for (const auto& p : a)
    if (p.point_id >= 0 && p.uv.allFinite()) uv_a[p.point_id] = p.uv;
  std::vector<double> d;
  for (const auto& p : b) {
    const auto it = uv_a.find(p.point_id);
    if (p.point_id < 0 || it == uv_a.end() || !p.uv.allFinite()) continue;
    const Eigen::Vector3d ray =
        R_b_a * Eigen::Vector3d((it->second.x() - K.cx) / K.fx, (it->second.y() - K.cy) / K.fy, 1);
    if (ray.z() <= 1e-9) continue;
    const Eigen::Vector2d uv(K.fx * ray.x() / ray.z() + K.cx, K.fy * ray.y() / ray.z() + K.cy);
    d.push_back((uv - p.uv).norm());
  }
  if (d.size() < 5) return 0.0;
  return UpperMedian(std::move(d));
}

}  // namespace

std::optional<inertial::ImageMotionFlag> ImageMotion(const window::FrameInput& previous_frame,
                                                     const window::FrameInput& frame,
                                                     double still_px) {
  std::map<int, Eigen::Vector2d> previous;
  for (const auto& p : previous_frame.points) previous[p.point_id] = p.uv;
  std::vector<double> d;
  for (const auto& p : frame.points) {
    const auto it = previous.find(p.point_id);
    if (it != previous.end()) d.push_back((p.uv - it->second).norm());
  }
  if (d.size() < 5) return std::nullopt;
  return inertial::ImageMotionFlag{frame.time, UpperMedian(std::move(d)) <= still_px};
}

struct VisualInertialInitializer::Impl {
  enum class Phase { kStaticTest, kDynamic, kDone, kFailed };
  VisualInertialOdometryOptions o;
  VisualInertialCalibration calib;
  Phase phase = Phase::kStaticTest;
  VioStart start;
  std::vector<VioInitEvent> events;
  // The dynamic search: start frame i, next second frame j; a vision-only run from (i, j).
  int i = 0, j = 1, f = 0;
  std::unique_ptr<window::SlidingWindowEstimator> run;
  std::vector<SE3d> T_vo;
  std::vector<int> keyframes;
  // init_extend_keyframes: the first successful alignment, kept while the run goes on to
  // extend_until keyframes; the start falls back to it when the run ends or a later one fails.
  std::optional<VioStart> aligned;
  int extend_until = 0;
  // init_extend_min_rotation_deg: the largest angle the body has turned from the run's first
  // keyframe to any later one (the gyroscope at the first alignment's gyro bias).
  double turned_deg = 0.0;

  double imu_gap_s = 0.0;  // the window's (WindowOptions(o, calib).inertial->imu_gap_s)
  // init_pair_budget: the two-view tests this Advance may still run (-1: no bound), and the
  // tests run so far.
  int budget = -1;
  int two_view_tests = 0;

  // The preintegration at zero bias, gaps bridged as the window bridges them.
  ImuPreintegration Preintegrate(const std::vector<sensor::ImuSample>& imu, double t0,
                                 double t1) const {
    return PreintegrateSamples(imu, t0, t1, sensor::ImuBias(), calib.imu, imu_gap_s);
  }
  bool Extended(const std::vector<window::FrameInput>& frames,
                const std::vector<sensor::ImuSample>& imu);
  void UpdateTurn(const std::vector<window::FrameInput>& frames,
                  const std::vector<sensor::ImuSample>& imu, std::size_t from);
  bool ExtensionDone(const std::vector<window::FrameInput>& frames, bool* keep_first);
  bool KeepFirst();
  bool Finish();
  bool StaticTest(const std::vector<window::FrameInput>& frames,
                  const std::vector<sensor::ImuSample>& imu,
                  const std::vector<inertial::ImageMotionFlag>& flags, bool end);
  bool StartStatic(const std::vector<window::FrameInput>& frames,
                   const std::vector<sensor::ImuSample>& imu,
                   const inertial::StaticInitResult& still);
  bool Dynamic(const std::vector<window::FrameInput>& frames,
               const std::vector<sensor::ImuSample>& imu, bool end);
  // The rotation of camera i in camera j from the gyroscope at zero bias.
  Eigen::Matrix3d GyroRotation(const std::vector<window::FrameInput>& frames,
                               const std::vector<sensor::ImuSample>& imu) const;
  // 0: the pair (i, j) is refused without its RANSAC, 1: tried (a run started from it or not),
  // -1: the budget of this frame is spent (the pair waits for the next frame).
  int NextPair(const std::vector<window::FrameInput>& frames,
               const std::vector<sensor::ImuSample>& imu);
  bool TryPair(const std::vector<window::FrameInput>& frames, const Eigen::Matrix3d& R_cj_ci);
  // false: no start yet; *hopeless: the run's poses disagree with the IMU (more keyframes of
  // the same run will not mend them: restart).
  bool TryAlignment(const std::vector<window::FrameInput>& frames,
                    const std::vector<sensor::ImuSample>& imu, bool* hopeless);
  void Restart();
  // Whether the run's keyframes span init_min_span_s (the alignment waits for it).
  bool SpanReached(const std::vector<window::FrameInput>& frames) const {
    return frames[keyframes.back()].time - frames[keyframes.front()].time >= o.init_min_span_s;
  }
};

// The still test on the IMU up to the newest frame (every block it reads then holds all the
// frames' flags that fall in it); at the end of the input on all of it.
bool VisualInertialInitializer::Impl::StaticTest(
    const std::vector<window::FrameInput>& frames, const std::vector<sensor::ImuSample>& imu,
    const std::vector<inertial::ImageMotionFlag>& flags, bool end) {
  inertial::StaticInitOptions so;
  so.gravity_magnitude = calib.gravity_magnitude;
  so.max_accel_std = o.static_max_accel_std;
  inertial::StaticInitResult still;
  if (end) {
    still = inertial::InitializeStatic(imu, so, frames.front().time, flags);
  } else {
    const double t_last = frames.back().time;
    const auto upto =
        std::upper_bound(imu.begin(), imu.end(), t_last,
                         [](double t, const sensor::ImuSample& s) { return t < s.t; });
    still = inertial::InitializeStatic(std::vector<sensor::ImuSample>(imu.begin(), upto), so,
                                       frames.front().time, flags);
    if (!MotionFound(still, so.block_seconds)) return false;  // wait: still so far
  }
  VioInitEvent e;
  e.event = "static_test";
  e.status = inertial::ToString(still.status);
  e.message = still.message;
  events.push_back(e);
  phase = Phase::kDynamic;
  if (still.success() && StartStatic(frames, imu, still)) {
    events.back().still = true;
    events.back().still_seconds = still.still_end - still.still_begin;
    events.back().gyro_bias = still.bias.gyro;
    events.back().up_b = still.up_b;
    phase = Phase::kDone;
    return true;
  }
  return false;
}

// Static: the still span at the start of the log; the window starts on its first two covered
// frames.
bool VisualInertialInitializer::Impl::StartStatic(const std::vector<window::FrameInput>& frames,
                                                  const std::vector<sensor::ImuSample>& imu,
                                                  const inertial::StaticInitResult& still) {
  const int n = static_cast<int>(frames.size());
  // The still test ran from the first frame's time: its span begins at the first IMU sample at or
  // after it, so every covered frame is in the span. (Testing frame times against still_begin
  // dropped frame 0 whenever a Kalibr timeshift_cam_imu put it between two IMU samples.)
  int a = 0;
  while (a < n && !Covered(imu, frames[a].time)) ++a;
  if (a + 1 >= n || !Covered(imu, frames[a + 1].time)) return false;
  start.method = "static";
  start.first = a;
  start.second = a + 1;
  sensor::BodyState st;
  st.t = frames[a].time;
  st.T_w_b = SE3d(still.R_w_b, Eigen::Vector3d::Zero());
  st.bias = still.bias;
  start.state_first = start.state_second = st;
  start.T_w_b.assign(a + 2, std::nullopt);
  start.T_w_b[a] = start.T_w_b[a + 1] = st.T_w_b;
  return true;
}

Eigen::Matrix3d VisualInertialInitializer::Impl::GyroRotation(
    const std::vector<window::FrameInput>& frames,
    const std::vector<sensor::ImuSample>& imu) const {
  const Eigen::Matrix3d R_bi_bj = Preintegrate(imu, frames[i].time, frames[j].time).DeltaR();
  const Eigen::Matrix3d R_b_c = calib.T_b_c.RotationMatrix();
  return R_b_c.transpose() * R_bi_bj.transpose() * R_b_c;
}

// A start frame is paired with the frames up to this many frames later.
constexpr int kPairRangeFrames = 30;

// The search is behind when its start frame's last pair (kPairRangeFrames on) is more than this
// many frames older than the newest frame (the unbounded search is never behind: it leaves a start
// frame once that pair is tested); only then does init_pair_min_rotated_parallax_px refuse pairs.
constexpr int kPairLagFrames = 5;

int VisualInertialInitializer::Impl::NextPair(const std::vector<window::FrameInput>& frames,
                                              const std::vector<sensor::ImuSample>& imu) {
  const bool behind = static_cast<int>(frames.size()) - 1 - (i + kPairRangeFrames) > kPairLagFrames;
  const bool parallax_test = behind && o.init_pair_min_rotated_parallax_px > 0.0;
  if (budget == 0 && !parallax_test) return -1;  // spent: no rotation needed
  const Eigen::Matrix3d R_cj_ci = GyroRotation(frames, imu);
  if (parallax_test && RotatedParallax(calib.camera.K, frames[i].points, frames[j].points,
                                       R_cj_ci) < o.init_pair_min_rotated_parallax_px)
    return 0;
  if (budget == 0) return -1;
  if (budget > 0) --budget;
  ++two_view_tests;
  return TryPair(frames, R_cj_ci) ? 1 : 0;
}

// A two-view start (i, j) checked against the gyroscope, and the vision-only run from it.
bool VisualInertialInitializer::Impl::TryPair(const std::vector<window::FrameInput>& frames,
                                              const Eigen::Matrix3d& R_cj_ci) {
  const double ti = frames[i].time, tj = frames[j].time;
  window::TwoViewOptions two_view;
  two_view.max_rotation_disagreement_deg =
      o.init_max_rotation_disagreement_deg + o.init_gyro_bias_bound * (tj - ti) * 180.0 / M_PI;
  const window::TwoViewResult tv = window::InitializeTwoView(calib.camera.K, frames[i].points,
                                                             frames[j].points, two_view, R_cj_ci);
  if (!tv.ok) return false;
  window::SlidingWindowOptions vo = WindowOptions(o, calib);
  vo.inertial.reset();
  vo.max_keyframe_interval_s = o.max_imu_factor_span_s;  // short IMU spans for the alignment
  vo.window_size = o.init_max_keyframes + 2;  // nothing is marginalized before the alignment
  if (o.init_two_view_line_sigma_scale > 0.0)
    vo.two_view_line_sigma_scale = o.init_two_view_line_sigma_scale;
  if (o.init_keyframe_max_rotation_deg > 0.0)
    vo.keyframe_max_rotation_deg = o.init_keyframe_max_rotation_deg;  // fast turns (the rate gate)
  run = std::make_unique<window::SlidingWindowEstimator>(calib.camera.K, vo);
  const window::InitializationResult init =
      run->Initialize(frames[i], SE3d(), frames[j], tv.T_b_a.Inverse());
  if (!init.ok) {
    run.reset();
    return false;
  }
  T_vo.assign(j + 1, SE3d());
  T_vo[i] = init.T_w_a;
  T_vo[j] = init.T_w_b;
  keyframes = {i, j};
  f = j + 1;
  return true;
}

// At a new keyframe of the run: the choice, then the alignment.
bool VisualInertialInitializer::Impl::TryAlignment(const std::vector<window::FrameInput>& frames,
                                                   const std::vector<sensor::ImuSample>& imu,
                                                   bool* hopeless) {
  inertial::AlignmentInput align;
  align.T_b_c = calib.T_b_c;
  align.t0 = frames[keyframes.front()].time;
  const std::vector<SE3d> kf = run->KeyframePoses();
  for (const SE3d& T : kf) align.T_c0_ck.push_back(kf.front().Inverse() * T);
  for (std::size_t k = 0; k + 1 < keyframes.size(); ++k) {
    align.preintegrations.push_back(
        Preintegrate(imu, frames[keyframes[k]].time, frames[keyframes[k + 1]].time));
  }
  inertial::InitializationChoiceOptions choice_options;
  choice_options.min_keyframes = o.init_min_keyframes;
  choice_options.min_excitation = o.init_min_excitation;
  inertial::StaticInitResult not_still;
  not_still.status = inertial::StaticInitStatus::kNotStill;
  const inertial::InitializationChoice choice = inertial::ChooseInitialization(
      not_still, static_cast<int>(keyframes.size()), inertial::ImuExcitation(align.preintegrations),
      choice_options);
  VioInitEvent e;
  e.frame = f;
  if (choice.method != inertial::InitializationMethod::kDynamic) {
    e.event = "wait";
    e.reason = choice.reason;
    events.push_back(e);
    return false;
  }
  inertial::AlignmentOptions ao;
  ao.gravity_magnitude = calib.gravity_magnitude;
  const inertial::AlignmentResult a = inertial::AlignVisualInertial(align, ao);
  e.event = "alignment";
  e.keyframes = static_cast<int>(keyframes.size());
  e.status = inertial::ToString(a.status);
  e.message = a.message;
  e.scale = a.scale;
  events.push_back(e);
  *hopeless = a.status == inertial::AlignmentStatus::kInconsistent;
  if (!a.success()) return false;
  start.method = "dynamic";
  start.first = keyframes.front();
  start.second = keyframes.back();
  start.state_first = a.states.front();
  start.state_second = a.states.back();
  for (std::size_t k = 0; k + 1 < keyframes.size(); ++k) {
    start.candidates.push_back(keyframes[k]);
    start.candidate_states.push_back(a.states[k]);
  }
  start.T_w_b.assign(f + 1, std::nullopt);
  for (int g = i; g <= f; ++g) {
    start.T_w_b[g] =
        AlignedBodyPose(T_vo[i], T_vo[g], a.scale, a.states.front().T_w_b, calib.T_b_c);
  }
  return true;
}

// The start is decided (start holds it).
bool VisualInertialInitializer::Impl::Finish() {
  phase = Phase::kDone;
  run.reset();
  return true;
}

// The extended run's alignment; the first one when it fails.
bool VisualInertialInitializer::Impl::Extended(const std::vector<window::FrameInput>& frames,
                                               const std::vector<sensor::ImuSample>& imu) {
  start = VioStart();
  bool hopeless = false;  // the first alignment stands either way
  if (!TryAlignment(frames, imu, &hopeless)) start = *aligned;
  return Finish();
}

// The turn of keyframes [from, newest] against the run's first keyframe, into turned_deg.
void VisualInertialInitializer::Impl::UpdateTurn(const std::vector<window::FrameInput>& frames,
                                                 const std::vector<sensor::ImuSample>& imu,
                                                 std::size_t from) {
  const double t0 = frames[keyframes.front()].time;
  sensor::ImuBias bias;
  bias.gyro = aligned->state_first.bias.gyro;
  for (std::size_t k = std::max<std::size_t>(from, 1); k < keyframes.size(); ++k) {
    const ImuPreintegration p =
        PreintegrateSamples(imu, t0, frames[keyframes[k]].time, bias, calib.imu, imu_gap_s);
    const double deg = Eigen::AngleAxisd(p.DeltaR()).angle() * 180.0 / M_PI;
    turned_deg = std::max(turned_deg, deg);
  }
}

// Whether the extension after the first alignment has ended: init_extend_keyframes more
// keyframes and, with init_extend_min_rotation_deg, the turn; *keep_first: the turn did not come
// (init_max_keyframes or init_extend_max_seconds reached), the start is the first alignment.
bool VisualInertialInitializer::Impl::ExtensionDone(const std::vector<window::FrameInput>& frames,
                                                    bool* keep_first) {
  *keep_first = false;
  const int n = static_cast<int>(keyframes.size());
  if (n < extend_until) return false;
  if (!(o.init_extend_min_rotation_deg > 0.0)) return true;
  if (turned_deg < o.init_extend_min_rotation_deg) {
    const double waited = frames[keyframes.back()].time - frames[aligned->second].time;
    *keep_first = n >= o.init_max_keyframes ||
                  (o.init_extend_max_seconds > 0.0 && waited >= o.init_extend_max_seconds);
    if (!*keep_first) return false;
  }
  VioInitEvent e;
  e.event = "extension";
  e.frame = f;
  e.keyframes = n;
  e.reason = "turned " + std::to_string(turned_deg) + " deg" +
             (*keep_first ? ", not enough: the first alignment" : "");
  events.push_back(e);
  return true;
}

// The extended run ended (lost, or the input did) before the extension did: the first alignment.
bool VisualInertialInitializer::Impl::KeepFirst() {
  VioInitEvent e;
  e.event = "extension";
  e.frame = f;
  e.keyframes = static_cast<int>(keyframes.size());
  e.reason =
      "the run ended after turning " + std::to_string(turned_deg) + " deg: the first alignment";
  events.push_back(e);
  start = *aligned;
  return Finish();
}

// The run from (i, j) gave no alignment: a later start frame.
void VisualInertialInitializer::Impl::Restart() {
  VioInitEvent e;
  e.event = "restart";
  e.frame = i;
  e.reason = "no alignment with this start";
  events.push_back(e);
  i = std::max(i, keyframes.size() > 2 ? keyframes[2] - 1 : j - 1) + 1;
  j = i + 1;
  run.reset();
}

// Advances the search as far as the frames so far allow (waits where it needs a later frame).
bool VisualInertialInitializer::Impl::Dynamic(const std::vector<window::FrameInput>& frames,
                                              const std::vector<sensor::ImuSample>& imu, bool end) {
  const int n = static_cast<int>(frames.size());
  while (true) {
    if (!run) {
      if (i + 1 >= n) {
        if (end) phase = Phase::kFailed;
        return false;
      }
      // The pair (i, j) (j up to kPairRangeFrames later), else the next start frame.
      const bool pair_possible = Covered(imu, frames[i].time) && j <= i + kPairRangeFrames;
      if (pair_possible && j >= n && !end) return false;  // wait for frame j
      if (!pair_possible || j >= n || !Covered(imu, frames[j].time)) {
        ++i;
        j = i + 1;
      } else {
        const int tried = NextPair(frames, imu);
        if (tried < 0) return false;  // the budget is spent: the pair waits for the next frame
        if (tried == 0) ++j;
      }
      continue;
    }
    const bool running = static_cast<int>(keyframes.size()) <= o.init_max_keyframes;
    if (running && f >= n && !end) return false;  // wait for frame f
    if (!running || f >= n || !Covered(imu, frames[f].time)) {
      if (aligned) return KeepFirst();
      Restart();
      continue;
    }
    const window::WindowFrameResult r = run->AddFrame(frames[f]);
    if (!r.ok) {
      if (aligned) return KeepFirst();
      Restart();
      continue;
    }
    T_vo.resize(f + 1);
    T_vo[f] = r.T_w_c;
    if (r.keyframe) {
      keyframes.push_back(f);
      bool hopeless = false;
      if (aligned) {
        if (o.init_extend_min_rotation_deg > 0.0) UpdateTurn(frames, imu, keyframes.size() - 1);
        bool keep_first = false;
        if (ExtensionDone(frames, &keep_first)) {
          if (keep_first) return Finish();  // start is the first alignment
          return Extended(frames, imu);
        }
      } else if (static_cast<int>(keyframes.size()) >= o.init_min_keyframes &&
                 SpanReached(frames) && TryAlignment(frames, imu, &hopeless)) {
        aligned = start;
        extend_until = std::min(static_cast<int>(keyframes.size()) + o.init_extend_keyframes,
                                o.init_max_keyframes);
        if (o.init_extend_min_rotation_deg > 0.0) UpdateTurn(frames, imu, 1);
        bool keep_first = false;
        if (ExtensionDone(frames, &keep_first)) return Finish();  // the first alignment
      }
      if (hopeless) {
        Restart();
        continue;
      }
    }
    ++f;
  }
}

VisualInertialInitializer::VisualInertialInitializer(const VisualInertialOdometryOptions& options,
                                                     const VisualInertialCalibration& calibration)
    : impl_(std::make_unique<Impl>()) {
  impl_->o = options;
  impl_->calib = calibration;
  impl_->imu_gap_s = WindowOptions(options, calibration).inertial->imu_gap_s;
}

VisualInertialInitializer::~VisualInertialInitializer() = default;

bool VisualInertialInitializer::Advance(const std::vector<window::FrameInput>& frames,
                                        const std::vector<sensor::ImuSample>& imu,
                                        const std::vector<inertial::ImageMotionFlag>& flags,
                                        bool end_of_input) {
  Impl& m = *impl_;
  if (m.phase == Impl::Phase::kDone) return true;
  if (m.phase == Impl::Phase::kFailed || frames.empty()) return false;
  if (m.phase == Impl::Phase::kStaticTest && m.StaticTest(frames, imu, flags, end_of_input))
    return true;
  m.budget = m.o.init_pair_budget > 0 && !end_of_input ? m.o.init_pair_budget : -1;
  if (m.phase == Impl::Phase::kDynamic) return m.Dynamic(frames, imu, end_of_input);
  return false;
}

bool VisualInertialInitializer::failed() const { return impl_->phase == Impl::Phase::kFailed; }
const VioStart& VisualInertialInitializer::start() const { return impl_->start; }
const std::vector<VioInitEvent>& VisualInertialInitializer::events() const { return impl_->events; }
int VisualInertialInitializer::two_view_tests() const { return impl_->two_view_tests; }

}  // namespace odometry
}  // namespace plucker
