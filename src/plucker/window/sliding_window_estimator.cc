#include "plucker/window/sliding_window_estimator.h"

#include <ceres/autodiff_cost_function.h>
#include <ceres/covariance.h>
#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <set>
#include <stdexcept>
#include <unordered_map>

#include "plucker/factors/held_extrinsic_factor.h"
#include "plucker/factors/imu_factor.h"
#include "plucker/factors/line_manifold.h"
#include "plucker/factors/point_reprojection_factor.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/geometry/orthonormal_line.h"
#include "plucker/window/frame_tracker.h"

namespace plucker {
namespace window {
namespace {

// r = S * Minus(T_w_c, prior) on the PoseManifold tangent.
struct PosePriorResidual {
  SE3d prior;
  Eigen::Matrix<double, 6, 6> S;
  template <typename T>
  bool operator()(const T* x, T* residual) const {
    // The rotation difference in the hemisphere of the prior's quaternion (q and -q are one
    // rotation; the prior may come with either sign).
    const SE3<T> X = SE3<T>::FromParameters(x);
    Eigen::Quaternion<T> dq = prior.rotation().cast<T>().conjugate() * X.rotation();
    if (dq.w() < T(0)) dq.coeffs() = -dq.coeffs();
    Eigen::Matrix<T, 6, 1> d;
    d.template head<3>() = LogUnitQuaternion<T>(dq);
    d.template tail<3>() = X.translation() - prior.translation().cast<T>();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r = S.cast<T>() * d;
    return true;
  }
};

// First-estimate Jacobians: the residual at the current values, the Jacobians with the blocks that
// have a first estimate replaced by it (falls back to the current values if that fails).
class FirstEstimateCost final : public ceres::CostFunction {
 public:
  FirstEstimateCost(ceres::CostFunction* inner, std::vector<const double*> first_estimates)
      : inner_(inner), fe_(std::move(first_estimates)) {
    set_num_residuals(inner->num_residuals());
    *mutable_parameter_block_sizes() = inner->parameter_block_sizes();
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    if (jacobians == nullptr) return inner_->Evaluate(parameters, residuals, nullptr);
    if (!inner_->Evaluate(parameters, residuals, nullptr)) return false;
    // On the stack for the window's factors (at most 6 blocks, 15 residuals: the IMU factor).
    constexpr std::size_t kMaxBlocks = 8, kMaxResiduals = 16;
    std::array<const double*, kMaxBlocks> at_fe_small;
    std::array<double, kMaxResiduals> scratch_small;
    std::vector<const double*> at_fe_large;
    std::vector<double> scratch_large;
    const double** at_fe = at_fe_small.data();
    double* scratch = scratch_small.data();
    if (fe_.size() > kMaxBlocks) {
      at_fe_large.resize(fe_.size());
      at_fe = at_fe_large.data();
    }
    if (static_cast<std::size_t>(num_residuals()) > kMaxResiduals) {
      scratch_large.resize(num_residuals());
      scratch = scratch_large.data();
    }
    for (std::size_t i = 0; i < fe_.size(); ++i)
      at_fe[i] = fe_[i] != nullptr ? fe_[i] : parameters[i];
    if (inner_->Evaluate(at_fe, scratch, jacobians)) return true;
    return inner_->Evaluate(parameters, scratch, jacobians);
  }

 private:
  std::unique_ptr<ceres::CostFunction> inner_;
  std::vector<const double*> fe_;
};

// r = S (x - x0) on a vector block (the inertial priors on a velocity or a bias block).
template <int kN>
struct VectorPriorResidual {
  Eigen::Matrix<double, kN, 1> x0;
  Eigen::Matrix<double, kN, kN> S;
  template <typename T>
  bool operator()(const T* x, T* residual) const {
    Eigen::Map<Eigen::Matrix<T, kN, 1>> r(residual);
    r = S.template cast<T>() *
        (Eigen::Map<const Eigen::Matrix<T, kN, 1>>(x) - x0.template cast<T>());
    return true;
  }
};

// Zero motion between two keyframes of a standing body (9 | 7 T_w_b_i, 7 T_w_b_j, 3 v_j):
// r = [Log(R_i^T R_j) / sigma_R, (p_j - p_i) / sigma_p, v_j / sigma_v].
struct ZeroMotionResidual {
  double sigma_R, sigma_p, sigma_v;
  template <typename T>
  bool operator()(const T* pose_i, const T* pose_j, const T* v_j, T* residual) const {
    const SE3<T> Ti = SE3<T>::FromParameters(pose_i), Tj = SE3<T>::FromParameters(pose_j);
    Eigen::Quaternion<T> dq = Ti.rotation().conjugate() * Tj.rotation();
    if (dq.w() < T(0)) dq.coeffs() = -dq.coeffs();
    Eigen::Map<Eigen::Matrix<T, 9, 1>> r(residual);
    r.template head<3>() = LogUnitQuaternion<T>(dq) / T(sigma_R);
    r.template segment<3>(3) = (Tj.translation() - Ti.translation()) / T(sigma_p);
    r.template tail<3>() = Eigen::Map<const Eigen::Matrix<T, 3, 1>>(v_j) / T(sigma_v);
    return true;
  }
};

enum class BlockKind { kPose, kPoint, kLine, kVelocity, kBias };

struct Frame {
  int index = 0;
  FrameInput input;
  double pose[7];                     // T_w_c, or T_w_b in the inertial mode
  std::vector<char> point_outlier;    // per input.points
  std::vector<char> segment_outlier;  // per input.segments
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
  ImuBias Bias() const {
    ImuBias b;
    b.gyro = Eigen::Vector3d(bias[0], bias[1], bias[2]);
    b.accel = Eigen::Vector3d(bias[3], bias[4], bias[5]);
    return b;
  }
  void SetState(const InertialState& s) {
    s.T_w_b.ToParameters(pose);
    for (int i = 0; i < 3; ++i) {
      v[i] = s.v_w(i);
      bias[i] = s.bias.gyro(i);
      bias[3 + i] = s.bias.accel(i);
    }
  }
  InertialState State() const {
    return {SE3d::FromParameters(pose), Eigen::Vector3d(v[0], v[1], v[2]), Bias()};
  }
};

struct PointLandmark {
  double p[3];
};

struct LineLandmark {
  LineAnchor anchor;
  double block[6];
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
};

bool ValidSegment(const sensor::SegmentObservation& s) {
  return s.line_id >= 0 && s.s_px.allFinite() && s.e_px.allFinite() &&
         (s.e_px - s.s_px).norm() >= 1.0;
}

bool ValidPoint(const sensor::PointObservation& p) { return p.point_id >= 0 && p.uv.allFinite(); }

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

struct SlidingWindowEstimator::Impl {
  PinholeIntrinsics K;
  SlidingWindowOptions opt;
  std::deque<std::unique_ptr<Frame>> keyframes;  // oldest first
  std::map<int, std::unique_ptr<PointLandmark>> points;
  std::map<int, std::unique_ptr<LineLandmark>> lines;
  std::unique_ptr<MarginalizationPrior> prior;
  std::vector<double*> prior_blocks;                // the prior's kept blocks (real storage)
  std::map<const double*, std::vector<double>> fe;  // their first estimates
  std::unique_ptr<ceres::LossFunction> loss;
  PoseManifold pose_manifold;
  LineManifold line_manifold;
  SE3d last_T_w_c, prev_T_w_c;
  // Tracks whose landmark went into a poses-only prior: never triangulated again.
  std::set<int> retired_points, retired_lines;
  std::vector<std::unique_ptr<RetainedPose>> retained;  // oldest first
  int prior_lines = 0;                                  // line blocks of the prior
  int frames_seen = 0;
  int next_index = 0;
  std::vector<sensor::ImuSample> imu;  // inertial mode: from just before the newest keyframe
  // Inertial mode: the extrinsic the window uses now (InertialOptions::T_b_c unless estimated),
  // its parameter block and its prior (InertialOptions::estimate_extrinsic).
  SE3d T_b_c;
  double extrinsic[7];
  bool extrinsic_free = false;
  std::unique_ptr<MarginalizationPrior> extrinsic_prior;

  bool InPrior(const double* block) const {
    return std::find(prior_blocks.begin(), prior_blocks.end(), block) != prior_blocks.end();
  }

  Eigen::Matrix2d PointSqrtInfo() const { return Eigen::Matrix2d::Identity() / opt.point_sigma_px; }
  Eigen::Matrix2d LineSqrtInfo() const { return Eigen::Matrix2d::Identity() / opt.line_sigma_px; }

  std::unique_ptr<Frame> MakeFrame(const FrameInput& input, const SE3d& T_w_c) {
    auto f = std::make_unique<Frame>();
    f->index = next_index++;
    f->input.time = input.time;
    f->input.T_w_c_prior = input.T_w_c_prior;
    f->input.prior_sqrt_information = input.prior_sqrt_information;
    f->input.stationary = input.stationary;
    for (const auto& p : input.points)
      if (ValidPoint(p)) f->input.points.push_back(p);
    if (opt.use_lines) {
      for (const auto& s : input.segments)
        if (ValidSegment(s)) f->input.segments.push_back(s);
    }
    f->point_outlier.assign(f->input.points.size(), 0);
    f->segment_outlier.assign(f->input.segments.size(), 0);
    if (opt.inertial) f->T_b_c = T_b_c;
    f->SetCameraPose(T_w_c);
    return f;
  }

  // --- inertial mode ---------------------------------------------------------------------------

  ceres::CostFunction* PointCost(const Eigen::Vector2d& uv) const {
    if (!opt.inertial) return PointReprojectionFactor::Create(K, uv, PointSqrtInfo());
    return new HeldExtrinsicFactor<3>(PointReprojectionFactorVI::Create(K, uv, PointSqrtInfo()),
                                      T_b_c);
  }

  ceres::CostFunction* LineCost(const sensor::SegmentObservation& s,
                                const LineAnchor& anchor) const {
    if (!opt.inertial) return AnchoredLineFactor::Create(K, s.s_px, s.e_px, LineSqrtInfo(), anchor);
    return new HeldExtrinsicFactor<6>(
        AnchoredLineFactorVI::Create(K, s.s_px, s.e_px, LineSqrtInfo(), anchor), T_b_c);
  }

  // --- extrinsic estimation (InertialOptions::estimate_extrinsic) -----------------------------

  // The extrinsic back to InertialOptions::T_b_c, held; with estimation, its prior: r = S
  // Minus(T_b_c, T_b_c given), S = diag(1 / sigma), the verified MarginalizationPrior of that
  // residual alone (nothing marginalized: the prior is the residual's linearisation, exact here
  // because the residual is linear in the PoseManifold Minus).
  void ResetExtrinsic() {
    if (!opt.inertial) return;
    T_b_c = opt.inertial->T_b_c;
    T_b_c.ToParameters(extrinsic);
    extrinsic_free = false;
    if (!opt.inertial->estimate_extrinsic || extrinsic_prior) return;
    Vector6d sigma;
    sigma << Eigen::Vector3d::Constant(opt.inertial->extrinsic_rotation_sigma),
        Eigen::Vector3d::Constant(opt.inertial->extrinsic_translation_sigma);
    const Eigen::Matrix<double, 6, 6> S = sigma.cwiseInverse().asDiagonal();
    std::vector<double> x0(extrinsic, extrinsic + 7);
    ceres::AutoDiffCostFunction<PosePriorResidual, 6, 7> cost(new PosePriorResidual{T_b_c, S});
    extrinsic_prior = std::make_unique<MarginalizationPrior>(MarginalizationPrior::Build(
        {{x0.data(), 7, &pose_manifold}}, {{&cost, nullptr, {x0.data()}}}, {}));
  }

  // Rotation excitation of the window: the second singular value (deg) of the keyframes' body
  // rotation vectors relative to the oldest keyframe (0 unless they turned about two axes).
  double RotationSpanDeg() const {
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    const Eigen::Quaterniond q0 = SE3d::FromParameters(keyframes.front()->pose).rotation();
    for (const auto& f : keyframes) {
      const Eigen::Vector3d w =
          LogSO3<double>(q0.conjugate() * SE3d::FromParameters(f->pose).rotation());
      M += w * w.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(M);
    return std::sqrt(std::max(eig.eigenvalues()(1), 0.0)) * 180.0 / M_PI;
  }

  // Frees the extrinsic for good once the window has rotated enough (see InertialOptions).
  void UpdateExtrinsicFree() {
    if (!opt.inertial || !opt.inertial->estimate_extrinsic || extrinsic_free) return;
    extrinsic_free = RotationSpanDeg() >= opt.inertial->extrinsic_min_rotation_deg;
  }

  // After a solve: the frames see the camera through the new estimate.
  void SyncExtrinsic() {
    if (!extrinsic_free) return;
    T_b_c = SE3d::FromParameters(extrinsic);
    T_b_c.ToParameters(extrinsic);  // normalized
    for (auto& f : keyframes) f->T_b_c = T_b_c;
  }

  // With the extrinsic free: the visual residuals (held-extrinsic factors on pose and landmark)
  // become the VI factors on (pose, extrinsic block, landmark).
  void UseExtrinsicBlock(std::vector<ResidualSpec>* residuals) {
    if (!extrinsic_free) return;
    for (ResidualSpec& r : *residuals) {
      if (r.frame == nullptr) continue;
      if (r.is_point) {
        const Eigen::Vector2d& uv = r.frame->input.points[r.observation].uv;
        r.cost.reset(PointReprojectionFactorVI::Create(K, uv, PointSqrtInfo()));
      } else {
        const sensor::SegmentObservation& seg = r.frame->input.segments[r.observation];
        r.cost.reset(AnchoredLineFactorVI::Create(K, seg.s_px, seg.e_px, LineSqrtInfo(),
                                                  lines.at(seg.line_id)->anchor));
      }
      r.blocks = {r.blocks[0], extrinsic, r.blocks[1]};
    }
  }

  // The IMU from time t0 to t1 at the bias `bias` (throws std::invalid_argument when the samples
  // do not cover the interval).
  ImuPreintegration Preintegrate(double t0, double t1, const ImuBias& bias) const {
    return PreintegrateSamples(imu, t0, t1, bias, opt.inertial->imu);
  }

  // The state at time t predicted from the newest keyframe, with the preintegration used.
  InertialState Predict(double t, std::unique_ptr<ImuPreintegration>* preintegration) const {
    const Frame& kf = *keyframes.back();
    *preintegration =
        std::make_unique<ImuPreintegration>(Preintegrate(kf.input.time, t, kf.Bias()));
    const InertialState s = kf.State();
    NavState n;
    n.R_w_b = s.T_w_b.RotationMatrix();
    n.p_w = s.T_w_b.translation();
    n.v_w = s.v_w;
    const NavState p = (*preintegration)->Predict(n, s.bias, opt.inertial->gravity_w);
    return {SE3d(p.R_w_b, p.p_w), p.v_w, s.bias};
  }

  // The IMU factor between keyframes k - 1 and k, and the priors of keyframe k.
  void AppendInertialResiduals(std::size_t k, std::vector<ResidualSpec>* out) const {
    Frame* f = keyframes[k].get();
    if (k > 0 && f->imu_from_previous) {
      Frame* p = keyframes[k - 1].get();
      ResidualSpec r;
      r.cost.reset(ImuFactor::Create(*f->imu_from_previous, opt.inertial->gravity_w));
      r.robust = false;
      r.blocks = {p->pose, p->v, p->bias, f->pose, f->v, f->bias};
      out->push_back(std::move(r));
      if (f->input.stationary && p->input.stationary) {
        const InertialOptions& o = *opt.inertial;
        ResidualSpec z;
        z.cost.reset(new ceres::AutoDiffCostFunction<ZeroMotionResidual, 9, 7, 7, 3>(
            new ZeroMotionResidual{o.stationary_rotation_sigma, o.stationary_position_sigma,
                                   o.stationary_velocity_sigma}));
        z.robust = false;
        z.blocks = {p->pose, f->pose, f->v};
        out->push_back(std::move(z));
      }
    }
    if (f->state_prior) {
      const InertialOptions& o = *opt.inertial;
      ResidualSpec rv;
      rv.cost.reset(
          new ceres::AutoDiffCostFunction<VectorPriorResidual<3>, 3, 3>(new VectorPriorResidual<3>{
              Eigen::Vector3d(f->v_prior), Eigen::Matrix3d::Identity() / o.velocity_prior_sigma}));
      rv.robust = false;
      rv.blocks = {f->v};
      out->push_back(std::move(rv));
      Eigen::Matrix<double, 6, 1> sigma;
      sigma << Eigen::Vector3d::Constant(o.gyro_bias_prior_sigma),
          Eigen::Vector3d::Constant(o.accel_bias_prior_sigma);
      ResidualSpec rb;
      rb.cost.reset(
          new ceres::AutoDiffCostFunction<VectorPriorResidual<6>, 6, 6>(new VectorPriorResidual<6>{
              Eigen::Matrix<double, 6, 1>(f->bias_prior), sigma.cwiseInverse().asDiagonal()}));
      rb.robust = false;
      rb.blocks = {f->bias};
      out->push_back(std::move(rb));
    }
  }

  // Integrates the IMU factors again whose start bias moved far from the linearisation point.
  void RepropagateImu() {
    if (!opt.inertial) return;
    for (std::size_t k = 1; k < keyframes.size(); ++k) {
      ImuPreintegration* p = keyframes[k]->imu_from_previous.get();
      if (!p) continue;
      const ImuBias b = keyframes[k - 1]->Bias();
      if ((b.gyro - p->BiasLinearisation().gyro).norm() > opt.inertial->repropagate_gyro_bias ||
          (b.accel - p->BiasLinearisation().accel).norm() > opt.inertial->repropagate_accel_bias) {
        p->Repropagate(b);
      }
    }
  }

  // Whitened squared residual of the IMU factor into the newest keyframe (0 if none).
  double NewestImuChi2() const {
    if (!opt.inertial || keyframes.size() < 2) return 0.0;
    std::vector<ResidualSpec> r;
    AppendInertialResiduals(keyframes.size() - 1, &r);
    if (r.empty() || r.front().cost->num_residuals() != 15) return 0.0;
    std::vector<const double*> params(r.front().blocks.begin(), r.front().blocks.end());
    Eigen::Matrix<double, 15, 1> res;
    if (!r.front().cost->Evaluate(params.data(), res.data(), nullptr)) return 0.0;
    return res.squaredNorm();
  }

  // Drops the IMU samples before the newest keyframe (one sample before it is kept).
  void PruneImu() {
    if (keyframes.empty() || imu.size() < 2) return;
    const double t = keyframes.back()->input.time;
    std::size_t keep = 0;
    while (keep + 1 < imu.size() && imu[keep + 1].t <= t) ++keep;
    imu.erase(imu.begin(), imu.begin() + static_cast<std::ptrdiff_t>(keep));
  }

  // --- residuals -------------------------------------------------------------------------------

  void AppendFrameResiduals(Frame* f, bool with_points, bool with_lines,
                            std::vector<ResidualSpec>* out) const {
    if (with_points) {
      for (std::size_t i = 0; i < f->input.points.size(); ++i) {
        if (f->point_outlier[i]) continue;
        const auto it = points.find(f->input.points[i].point_id);
        if (it == points.end()) continue;
        ResidualSpec r;
        r.cost.reset(PointCost(f->input.points[i].uv));
        r.blocks = {f->pose, it->second->p};
        r.frame = f;
        r.observation = static_cast<int>(i);
        out->push_back(std::move(r));
      }
    }
    if (with_lines) {
      for (std::size_t i = 0; i < f->input.segments.size(); ++i) {
        if (f->segment_outlier[i]) continue;
        const auto it = lines.find(f->input.segments[i].line_id);
        if (it == lines.end()) continue;
        const auto& s = f->input.segments[i];
        ResidualSpec r;
        r.cost.reset(LineCost(s, it->second->anchor));
        r.blocks = {f->pose, it->second->block};
        r.frame = f;
        r.observation = static_cast<int>(i);
        r.is_point = false;
        out->push_back(std::move(r));
      }
    }
    if (f->input.T_w_c_prior) {
      ResidualSpec r;
      r.cost.reset(new ceres::AutoDiffCostFunction<PosePriorResidual, 6, 7>(
          new PosePriorResidual{*f->input.T_w_c_prior, f->input.prior_sqrt_information}));
      r.robust = false;
      r.blocks = {f->pose};
      out->push_back(std::move(r));
    }
  }

  // The caller's stationary flag, believed only while the body moves slower than
  // InertialOptions::stationary_max_speed (an image test alone takes forward motion for standing).
  bool BelievedStationary(bool flag, const Eigen::Vector3d& v_w) const {
    return flag && v_w.norm() < opt.inertial->stationary_max_speed;
  }
  bool RetainLinePoses() const {
    return opt.use_lines && opt.keep_marginalized_lines && opt.retain_line_observer_poses &&
           !opt.inertial && opt.prior_blocks == SlidingWindowOptions::PriorBlocks::kLandmarks;
  }

  // The observations of the retained poses whose line exists (and, when `only` is given, is in
  // it), as residuals on (retained pose, line).
  void AppendRetainedResiduals(std::vector<ResidualSpec>* out, const std::set<int>* only = nullptr,
                               const RetainedPose* from = nullptr) const {
    for (const auto& rp : retained) {
      if (from && rp.get() != from) continue;
      for (const sensor::SegmentObservation& seg : rp->segments) {
        const auto it = lines.find(seg.line_id);
        if (it == lines.end() || (only && !only->count(seg.line_id))) continue;
        ResidualSpec r;
        r.cost.reset(LineCost(seg, it->second->anchor));
        r.blocks = {rp->pose, it->second->block};
        r.is_point = false;
        out->push_back(std::move(r));
      }
    }
  }

  // Drops the retained observations whose line is gone (or, with `cull`, whose residual exceeds
  // the outlier threshold), then the retained poses left with none that are not in the prior
  // (those in it leave at the next marginalization). Returns the observations culled.
  int PruneRetained(bool cull) {
    int culled = 0;
    for (auto& rp : retained) {
      std::vector<sensor::SegmentObservation> keep;
      for (const sensor::SegmentObservation& seg : rp->segments) {
        const auto it = lines.find(seg.line_id);
        if (it == lines.end()) continue;
        if (cull) {
          std::unique_ptr<ceres::CostFunction> cost(LineCost(seg, it->second->anchor));
          double res[2];
          const double* params[2] = {rp->pose, it->second->block};
          if (!cost->Evaluate(params, res, nullptr) || !std::isfinite(res[0]) ||
              !std::isfinite(res[1]) || std::hypot(res[0], res[1]) > opt.outlier_sigmas) {
            ++culled;
            continue;
          }
        }
        keep.push_back(seg);
      }
      rp->segments.swap(keep);
    }
    retained.erase(std::remove_if(retained.begin(), retained.end(),
                                  [this](const std::unique_ptr<RetainedPose>& rp) {
                                    return rp->segments.empty() && !InPrior(rp->pose);
                                  }),
                   retained.end());
    return culled;
  }

  BlockKind KindOf(const double* block) const {
    if (block == extrinsic) return BlockKind::kPose;
    for (const auto& rp : retained)
      if (rp->pose == block) return BlockKind::kPose;
    for (const auto& f : keyframes) {
      if (f->pose == block) return BlockKind::kPose;
      if (f->v == block) return BlockKind::kVelocity;
      if (f->bias == block) return BlockKind::kBias;
    }
    for (const auto& [id, l] : lines)
      if (l->block == block) return BlockKind::kLine;
    return BlockKind::kPoint;
  }

  const ceres::Manifold* ManifoldOf(BlockKind kind) const {
    if (kind == BlockKind::kPose) return &pose_manifold;
    if (kind == BlockKind::kLine) return &line_manifold;
    return nullptr;
  }

  static int AmbientSize(BlockKind kind) {
    if (kind == BlockKind::kBias) return 6;
    return kind == BlockKind::kPose ? 7 : (kind == BlockKind::kLine ? 6 : 3);
  }

  // Where an observation residual of the window problem came from (for culling).
  struct ObservationBlock {
    ceres::ResidualBlockId id;
    Frame* frame;
    int observation;
    bool is_point;
  };

  // Marks the observations whose residual in `problem` (at the current values) cannot be
  // evaluated or exceeds the outlier threshold; returns the number marked.
  int CullOutliers(const ceres::Problem& problem,
                   const std::vector<ObservationBlock>& observations) const {
    int culled = 0;
    for (const ObservationBlock& o : observations) {
      double res[2];
      const bool ok = problem.EvaluateResidualBlock(o.id, false, nullptr, res, nullptr) &&
                      std::isfinite(res[0]) && std::isfinite(res[1]);
      if (ok && std::hypot(res[0], res[1]) <= opt.outlier_sigmas) continue;
      (o.is_point ? o.frame->point_outlier : o.frame->segment_outlier)[o.observation] = 1;
      ++culled;
    }
    return culled;
  }

  // --- tracking --------------------------------------------------------------------------------

  struct TrackResult {
    bool ok = false;
    SE3d T_w_c;
    int points = 0, lines = 0, iterations = 0;
  };

  // Inertial mode: the prior the IMU prediction puts on a frame's body pose T_w_b (PoseManifold
  // tangent: body rotation, world position). Its covariance is the preintegration's from the
  // newest keyframe (rotation and position, given the keyframe's state) plus the keyframe's
  // velocity uncertainty carried over the time since it, (tracking_velocity_sigma dt)^2 per axis.
  ceres::CostFunction* ImuPosePrior(const InertialState& predicted,
                                    const ImuPreintegration& preintegration) const {
    const Eigen::Matrix3d R_w_i = keyframes.back()->State().T_w_b.RotationMatrix();
    const Matrix9d C = preintegration.Covariance();  // [dtheta, dv, dp] in the body at i
    Eigen::Matrix<double, 6, 6> cov;
    cov.topLeftCorner<3, 3>() = C.topLeftCorner<3, 3>();
    cov.topRightCorner<3, 3>() = C.block<3, 3>(0, 6) * R_w_i.transpose();
    cov.bottomLeftCorner<3, 3>() = cov.topRightCorner<3, 3>().transpose();
    const double sv = opt.inertial->tracking_velocity_sigma * preintegration.Dt();
    cov.bottomRightCorner<3, 3>() =
        R_w_i * C.block<3, 3>(6, 6) * R_w_i.transpose() + sv * sv * Eigen::Matrix3d::Identity();
    if (opt.inertial->estimate_extrinsic) {
      // The tracking sees the camera through the extrinsic's estimate, held: its uncertainty
      // (the prior's sigmas) separates the visual body pose from the IMU's too.
      const double sr = opt.inertial->extrinsic_rotation_sigma;
      const double st = opt.inertial->extrinsic_translation_sigma;
      cov.topLeftCorner<3, 3>() += sr * sr * Eigen::Matrix3d::Identity();
      cov.bottomRightCorner<3, 3>() += st * st * Eigen::Matrix3d::Identity();
    }
    // S = L^-1 with cov = L L^T: S^T S = cov^-1.
    const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(cov);
    if (llt.info() != Eigen::Success) return nullptr;
    const Eigen::Matrix<double, 6, 6> S =
        llt.matrixL().solve(Eigen::Matrix<double, 6, 6>::Identity());
    if (!S.allFinite()) return nullptr;
    return new ceres::AutoDiffCostFunction<PosePriorResidual, 6, 7>(
        new PosePriorResidual{predicted.T_w_b, S});
  }

  // `prior` (optional): a pose-only term on the frame's pose block (ImuPosePrior).
  TrackResult Track(Frame* f, const SE3d& guess, const ceres::CostFunction* prior = nullptr) const {
    TrackResult result;
    result.T_w_c = guess;
    f->SetCameraPose(guess);
    // One term per observation of an existing landmark (outliers of earlier rounds left out).
    struct Observation {
      std::unique_ptr<ceres::CostFunction> cost;
      const double* landmark;
      int index;
      bool is_point;
    };
    std::vector<Observation> obs;
    for (std::size_t i = 0; i < f->input.points.size(); ++i) {
      const auto it = points.find(f->input.points[i].point_id);
      if (f->point_outlier[i] || it == points.end()) continue;
      obs.push_back({std::unique_ptr<ceres::CostFunction>(PointCost(f->input.points[i].uv)),
                     it->second->p, static_cast<int>(i), true});
    }
    if (opt.use_lines) {
      for (std::size_t i = 0; i < f->input.segments.size(); ++i) {
        const auto it = lines.find(f->input.segments[i].line_id);
        if (f->segment_outlier[i] || it == lines.end()) continue;
        obs.push_back({std::unique_ptr<ceres::CostFunction>(
                           LineCost(f->input.segments[i], it->second->anchor)),
                       it->second->block, static_cast<int>(i), false});
      }
    }
    // Flags the observations that cannot be evaluated at the pose (behind the camera) or, with
    // `threshold`, whose whitened residual exceeds it; returns how many.
    const auto flag = [&](double threshold) {
      int flagged = 0;
      for (Observation& o : obs) {
        if (o.cost == nullptr) continue;
        double res[2];
        const double* params[2] = {f->pose, o.landmark};
        const bool ok = o.cost->Evaluate(params, res, nullptr) && std::isfinite(res[0]) &&
                        std::isfinite(res[1]);
        if (ok && std::hypot(res[0], res[1]) <= threshold) continue;
        (o.is_point ? f->point_outlier : f->segment_outlier)[o.index] = 1;
        o.cost.reset();
        ++flagged;
      }
      return flagged;
    };
    flag(std::numeric_limits<double>::infinity());
    PoseRefinementOptions ro;
    ro.max_iterations = opt.max_tracking_iterations;
    for (int round = 0; round < 2; ++round) {
      std::vector<PoseTerm> terms;
      for (const Observation& o : obs)
        if (o.cost) terms.push_back({o.cost.get(), o.landmark});
      if (terms.size() < 6) return result;
      if (prior) terms.push_back({prior, nullptr});
      result.iterations += RefinePose(terms, loss.get(), ro, f->pose).iterations;
      if (flag(opt.outlier_sigmas) == 0) break;
    }
    result.points = result.lines = 0;
    for (std::size_t i = 0; i < f->input.points.size(); ++i)
      if (!f->point_outlier[i] && points.count(f->input.points[i].point_id)) ++result.points;
    for (std::size_t i = 0; i < f->input.segments.size(); ++i)
      if (!f->segment_outlier[i] && lines.count(f->input.segments[i].line_id)) ++result.lines;
    result.T_w_c = f->T_w_c();
    result.ok = result.points + result.lines >= 6 && f->T_w_c().translation().allFinite();
    return result;
  }

  // The pose from PnP RANSAC of the frame's point tracks against the window's points, or nullopt.
  std::optional<SE3d> PnpPose(const Frame& f) const {
    std::vector<cv::Point3d> object;
    std::vector<cv::Point2d> image;
    for (const auto& p : f.input.points) {
      const auto it = points.find(p.point_id);
      if (it == points.end()) continue;
      object.emplace_back(it->second->p[0], it->second->p[1], it->second->p[2]);
      image.emplace_back(p.uv.x(), p.uv.y());
    }
    if (static_cast<int>(object.size()) < std::max(opt.pnp_min_inliers, 6)) return std::nullopt;
    const cv::Matx33d Kcv(K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1);
    cv::Mat rvec, tvec;
    std::vector<int> inliers;
    const bool ok = cv::solvePnPRansac(object, image, Kcv, cv::noArray(), rvec, tvec, false, 200,
                                       static_cast<float>(opt.pnp_threshold_px), 0.999, inliers,
                                       cv::SOLVEPNP_EPNP);
    if (!ok || static_cast<int>(inliers.size()) < opt.pnp_min_inliers) return std::nullopt;
    cv::Matx33d R;
    cv::Rodrigues(rvec, R);
    Eigen::Matrix3d R_c_w;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) R_c_w(r, c) = R(r, c);
    const Eigen::Vector3d t_c_w(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
    if (!R_c_w.allFinite() || !t_c_w.allFinite()) return std::nullopt;
    return SE3d(Eigen::Quaterniond(R_c_w), t_c_w).Inverse();
  }

  // --- keyframe policy -------------------------------------------------------------------------

  double Parallax(const Frame& f) const {
    const Frame& kf = *keyframes.back();
    std::unordered_map<int, Eigen::Vector2d> kf_uv;
    for (const auto& p : kf.input.points) kf_uv[p.point_id] = p.uv;
    const Eigen::Matrix3d R_c_kf =
        f.T_w_c().RotationMatrix().transpose() * kf.T_w_c().RotationMatrix();
    std::vector<double> d;
    for (const auto& p : f.input.points) {
      const auto it = kf_uv.find(p.point_id);
      if (it == kf_uv.end()) continue;
      const Eigen::Vector3d ray = R_c_kf * Eigen::Vector3d((it->second.x() - K.cx) / K.fx,
                                                           (it->second.y() - K.cy) / K.fy, 1.0);
      if (ray.z() <= 1e-6) continue;
      const Eigen::Vector2d uv(K.fx * ray.x() / ray.z() + K.cx, K.fy * ray.y() / ray.z() + K.cy);
      d.push_back((uv - p.uv).norm());
    }
    if (d.size() >= 8) return Median(d);
    // Too few common points (scarce points, many lines): the parallax the baseline to the newest
    // keyframe induces at the median depth of the tracked landmarks, f * baseline / depth.
    const SE3d T_c_w = f.T_w_c().Inverse();
    const Eigen::Vector3d centre = f.T_w_c().translation();
    std::vector<double> depth;
    for (std::size_t i = 0; i < f.input.points.size(); ++i) {
      const auto it = points.find(f.input.points[i].point_id);
      if (it == points.end() || f.point_outlier[i]) continue;
      const double z =
          (T_c_w * Eigen::Vector3d(it->second->p[0], it->second->p[1], it->second->p[2])).z();
      if (z > 0.0) depth.push_back(z);
    }
    for (std::size_t i = 0; i < f.input.segments.size(); ++i) {
      const auto it = lines.find(f.input.segments[i].line_id);
      if (it == lines.end() || f.segment_outlier[i]) continue;
      const Line6d L_w = WorldFromAnchored(
          PluckerFromOrthonormal(OrthonormalLine::FromParameters(it->second->block)),
          it->second->anchor);
      const std::optional<double> dist = PointLineDistance(L_w, centre);
      if (dist && *dist > 0.0) depth.push_back(*dist);
    }
    if (depth.empty()) return 0.0;
    const double baseline = (centre - kf.T_w_c().translation()).norm();
    return 0.5 * (K.fx + K.fy) * baseline / Median(depth);
  }

  // --- triangulation ---------------------------------------------------------------------------

  // New landmarks for the tracks of keyframe `f` (the newest) that have none yet.
  void Triangulate(const Frame& f, int* new_points, int* new_lines) {
    for (const auto& obs : f.input.points) {
      if (points.count(obs.point_id) || retired_points.count(obs.point_id)) continue;
      std::vector<SE3d> poses;
      std::vector<Eigen::Vector2d> uvs;
      for (const auto& kf : keyframes) {
        for (std::size_t i = 0; i < kf->input.points.size(); ++i) {
          if (kf->input.points[i].point_id != obs.point_id || kf->point_outlier[i]) continue;
          poses.push_back(kf->T_w_c());
          uvs.push_back(kf->input.points[i].uv);
          break;
        }
      }
      if (poses.size() < 2) continue;
      const PointTriangulationResult t = TriangulatePoint(K, poses, uvs, opt.point_triangulation);
      if (!t.ok() || t.final_rms_px > 2.0 * opt.point_sigma_px + 1.0) continue;
      auto lm = std::make_unique<PointLandmark>();
      for (int i = 0; i < 3; ++i) lm->p[i] = t.p_w(i);
      points[obs.point_id] = std::move(lm);
      ++*new_points;
    }
    if (!opt.use_lines) return;
    for (const auto& obs : f.input.segments) {
      if (lines.count(obs.line_id) || retired_lines.count(obs.line_id)) continue;
      std::vector<LineObservation> views;
      for (const auto& kf : keyframes) {
        for (std::size_t i = 0; i < kf->input.segments.size(); ++i) {
          const auto& s = kf->input.segments[i];
          if (s.line_id != obs.line_id || kf->segment_outlier[i]) continue;
          views.push_back({kf->T_w_c(), s.s_px, s.e_px});
          break;
        }
      }
      if (views.size() < 2) continue;
      const LineTriangulationResult t = TriangulateLine(K, views, opt.line_triangulation);
      if (!t.ok() || t.sigma_ratio > opt.max_line_sigma_ratio) continue;
      LineAnchor anchor;
      if (opt.condition_far_lines)
        anchor = MakeLineAnchor(t.L_w, views.front().T_w_c.translation());
      const std::optional<OrthonormalLine> o =
          OrthonormalFromPlucker(AnchoredFromWorld(t.L_w, anchor));
      if (!o) continue;
      auto lm = std::make_unique<LineLandmark>();
      lm->anchor = anchor;
      o->ToParameters(lm->block);
      lines[obs.line_id] = std::move(lm);
      ++*new_lines;
    }
  }

  // --- window solve ----------------------------------------------------------------------------

  std::vector<const double*> FirstEstimatesOf(const std::vector<double*>& blocks) const {
    std::vector<const double*> out(blocks.size(), nullptr);
    if (!opt.first_estimate_jacobians) return out;
    for (std::size_t i = 0; i < blocks.size(); ++i) {
      const auto it = fe.find(blocks[i]);
      if (it != fe.end()) out[i] = it->second.data();
    }
    return out;
  }

  bool HasPosePrior() const {
    for (const auto& f : keyframes)
      if (f->input.T_w_c_prior) return true;
    return false;
  }

  // Builds the window problem into `problem` (culling what cannot be evaluated first). Returns
  // the number of residual blocks; `observations` (optional): the keyframes' observation blocks.
  int BuildProblem(ceres::Problem* problem, bool hold_gauge,
                   std::vector<ObservationBlock>* observations = nullptr) {
    std::vector<ResidualSpec> residuals;
    for (auto& f : keyframes) AppendFrameResiduals(f.get(), true, opt.use_lines, &residuals);
    if (opt.inertial) {
      for (std::size_t k = 0; k < keyframes.size(); ++k) AppendInertialResiduals(k, &residuals);
    }
    AppendRetainedResiduals(&residuals);
    UseExtrinsicBlock(&residuals);
    if (extrinsic_free) {
      ResidualSpec r;
      r.cost.reset(extrinsic_prior->CreateCostFunction());
      r.robust = false;
      r.blocks = {extrinsic};
      residuals.push_back(std::move(r));
    }
    int n = 0;
    for (ResidualSpec& r : residuals) {
      if (r.frame != nullptr) {
        double res[2];
        std::vector<const double*> params(r.blocks.begin(), r.blocks.end());
        if (!r.cost->Evaluate(params.data(), res, nullptr)) {
          (r.is_point ? r.frame->point_outlier : r.frame->segment_outlier)[r.observation] = 1;
          continue;
        }
      }
      const std::vector<const double*> first = FirstEstimatesOf(r.blocks);
      ceres::CostFunction* cost = r.cost.release();
      if (std::any_of(first.begin(), first.end(), [](const double* p) { return p != nullptr; })) {
        cost = new FirstEstimateCost(cost, first);
      }
      const ceres::ResidualBlockId id =
          problem->AddResidualBlock(cost, r.robust ? loss.get() : nullptr, r.blocks);
      if (observations && r.frame != nullptr) {
        observations->push_back({id, r.frame, r.observation, r.is_point});
      }
      ++n;
    }
    if (prior) {
      problem->AddResidualBlock(prior->CreateCostFunction(), nullptr, prior_blocks);
      ++n;
    }
    for (auto& f : keyframes) {
      if (problem->HasParameterBlock(f->pose)) problem->SetManifold(f->pose, &pose_manifold);
    }
    if (problem->HasParameterBlock(extrinsic)) problem->SetManifold(extrinsic, &pose_manifold);
    for (auto& rp : retained) {
      if (problem->HasParameterBlock(rp->pose)) problem->SetManifold(rp->pose, &pose_manifold);
    }
    for (auto& [id, l] : lines) {
      if (problem->HasParameterBlock(l->block)) problem->SetManifold(l->block, &line_manifold);
    }
    if (hold_gauge && !prior && !HasPosePrior() &&
        problem->HasParameterBlock(keyframes.front()->pose)) {
      problem->SetParameterBlockConstant(keyframes.front()->pose);
    }
    return n;
  }

  static ceres::Problem::Options ProblemOptions() {
    ceres::Problem::Options po;
    po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    return po;
  }

  void SolveWindow(FrameResult* result) {
    RepropagateImu();
    UpdateExtrinsicFree();
    ceres::Problem problem(ProblemOptions());
    std::vector<ObservationBlock> observations;
    result->residuals = BuildProblem(&problem, true, &observations);
    ceres::Solver::Options so;
    // With a poses-only prior every landmark is eliminated and the reduced system (poses, and
    // velocities and biases in the inertial mode) is small: dense, its Cholesky factorization
    // costs less than SuiteSparse's symbolic work (corridor, 600 frames: the linear solver 2.5 s
    // -> 1.2 s over the run, the same trajectory). The landmark prior keeps landmarks in the
    // reduced system: sparse.
    so.linear_solver_type = opt.prior_blocks == SlidingWindowOptions::PriorBlocks::kPoses
                                ? ceres::DENSE_SCHUR
                                : ceres::SPARSE_SCHUR;
    so.max_num_iterations = opt.max_iterations;
    so.num_threads = 1;
    so.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    result->window_iterations = static_cast<int>(summary.iterations.size()) - 1;
    result->initial_cost = summary.initial_cost;
    result->final_cost = summary.final_cost;
    SyncExtrinsic();
    // Cull outliers (the problem's own residual blocks, at the solution) and landmarks left with
    // too few observations.
    result->culled_observations = CullOutliers(problem, observations);
    result->culled_observations += PruneRetained(true);
    RemoveWeakLandmarks();
  }

  // Landmarks observed (as inliers) by fewer than two keyframes and not in the prior.
  void RemoveWeakLandmarks() {
    std::map<int, int> point_count, line_count;
    for (const auto& f : keyframes) {
      for (std::size_t i = 0; i < f->input.points.size(); ++i)
        if (!f->point_outlier[i]) ++point_count[f->input.points[i].point_id];
      for (std::size_t i = 0; i < f->input.segments.size(); ++i)
        if (!f->segment_outlier[i]) ++line_count[f->input.segments[i].line_id];
    }
    for (const auto& rp : retained)
      for (const auto& seg : rp->segments) ++line_count[seg.line_id];
    for (auto it = points.begin(); it != points.end();) {
      if (point_count[it->first] < 2 && !InPrior(it->second->p)) {
        it = points.erase(it);
      } else {
        ++it;
      }
    }
    for (auto it = lines.begin(); it != lines.end();) {
      if (line_count[it->first] < 2 && !InPrior(it->second->block)) {
        it = lines.erase(it);
      } else {
        ++it;
      }
    }
    PruneRetained(false);
  }

  // --- marginalization -------------------------------------------------------------------------

  void MarginalizeOldest(FrameResult* result) {
    Frame* f0 = keyframes.front().get();
    std::set<int> points_kept, lines_kept;  // observed by a remaining keyframe
    for (std::size_t k = 1; k < keyframes.size(); ++k) {
      const Frame& f = *keyframes[k];
      for (std::size_t i = 0; i < f.input.points.size(); ++i)
        if (!f.point_outlier[i]) points_kept.insert(f.input.points[i].point_id);
      for (std::size_t i = 0; i < f.input.segments.size(); ++i)
        if (!f.segment_outlier[i]) lines_kept.insert(f.input.segments[i].line_id);
    }
    std::vector<ResidualSpec> residuals;
    AppendFrameResiduals(f0, true, opt.use_lines && opt.keep_marginalized_lines, &residuals);
    UseExtrinsicBlock(&residuals);  // the extrinsic stays: k0's information on it enters the prior
    // Retained poses: k0's observations of the lines that stay are kept as they are, and k0's
    // pose with them (not eliminated); the retained observations of the lines that leave now
    // join the marginalization, and a retained pose left without observations leaves with them.
    std::unique_ptr<RetainedPose> k0_retained;
    std::set<int> lines_leaving;
    std::vector<const RetainedPose*> retained_out;  // retained poses that leave now
    if (RetainLinePoses()) {
      std::vector<ResidualSpec> rest;
      for (ResidualSpec& r : residuals) {
        const bool kept_line = !r.is_point && r.frame == f0 &&
                               lines_kept.count(f0->input.segments[r.observation].line_id);
        if (!kept_line) {
          rest.push_back(std::move(r));
          continue;
        }
        if (!k0_retained) k0_retained = std::make_unique<RetainedPose>();
        k0_retained->segments.push_back(f0->input.segments[r.observation]);
        ++result->held_line_observations;
      }
      residuals.swap(rest);
      for (const auto& [id, l] : lines)
        if (!lines_kept.count(id)) lines_leaving.insert(id);
      // A retained pose leaves when it observes no line that stays, or, beyond
      // max_retained_poses, the oldest leave: their observations of the lines that stay are
      // dropped (or, retained_overflow_into_prior, enter the prior with the lines at their
      // estimates of that moment); those of the lines that leave are marginalized with them.
      const int over = static_cast<int>(retained.size()) + (k0_retained ? 1 : 0) -
                       std::max(opt.max_retained_poses, 0);
      for (std::size_t i = 0; i < retained.size(); ++i) {
        const RetainedPose* rp = retained[i].get();
        const bool observes = std::any_of(
            rp->segments.begin(), rp->segments.end(), [&](const sensor::SegmentObservation& seg) {
              return lines.count(seg.line_id) && !lines_leaving.count(seg.line_id);
            });
        const bool leaves = !observes || static_cast<int>(i) < over;
        if (leaves) retained_out.push_back(rp);
        const bool all = leaves && opt.retained_overflow_into_prior;
        if (leaves && !all) {
          for (const sensor::SegmentObservation& seg : rp->segments)
            if (lines.count(seg.line_id) && !lines_leaving.count(seg.line_id))
              ++result->dropped_retained_line_observations;
        }
        AppendRetainedResiduals(&residuals, all ? nullptr : &lines_leaving, rp);
      }
    }
    if (opt.inertial) {
      AppendInertialResiduals(0, &residuals);  // the first keyframe's priors
      AppendInertialResiduals(1, &residuals);  // the IMU factor to the successor (and its priors)
    }
    if (opt.use_lines && !opt.keep_marginalized_lines) {
      for (std::size_t i = 0; i < f0->input.segments.size(); ++i)
        if (!f0->segment_outlier[i] && lines.count(f0->input.segments[i].line_id))
          ++result->dropped_line_observations;
    }
    // Drop residuals that cannot be evaluated.
    residuals.erase(std::remove_if(residuals.begin(), residuals.end(),
                                   [](const ResidualSpec& r) {
                                     std::vector<const double*> params(r.blocks.begin(),
                                                                       r.blocks.end());
                                     std::vector<double> res(r.cost->num_residuals());
                                     return !r.cost->Evaluate(params.data(), res.data(), nullptr);
                                   }),
                    residuals.end());
    if (prior) {
      ResidualSpec r;
      r.cost.reset(prior->CreateCostFunction());
      r.robust = false;
      r.blocks = prior_blocks;
      residuals.push_back(std::move(r));
    }
    // Blocks touched, and the ones to remove.
    std::vector<double*> touched;
    for (const ResidualSpec& r : residuals)
      for (double* b : r.blocks)
        if (std::find(touched.begin(), touched.end(), b) == touched.end()) touched.push_back(b);
    std::vector<double*> remove;
    std::vector<int> remove_points, remove_lines;
    for (const auto& [id, p] : points) {
      if (points_kept.count(id)) continue;
      remove_points.push_back(id);
      if (std::find(touched.begin(), touched.end(), p->p) != touched.end()) remove.push_back(p->p);
    }
    for (const auto& [id, l] : lines) {
      if (lines_kept.count(id)) continue;
      remove_lines.push_back(id);
      if (std::find(touched.begin(), touched.end(), l->block) != touched.end())
        remove.push_back(l->block);
    }
    const bool pose_touched = std::find(touched.begin(), touched.end(), f0->pose) != touched.end();
    if (pose_touched && !k0_retained) remove.push_back(f0->pose);
    for (const RetainedPose* rp : retained_out)
      if (std::find(touched.begin(), touched.end(), rp->pose) != touched.end())
        remove.push_back(const_cast<double*>(rp->pose));
    for (double* b : {f0->v, f0->bias}) {
      if (std::find(touched.begin(), touched.end(), b) != touched.end()) remove.push_back(b);
    }

    std::unique_ptr<MarginalizationPrior> next;
    std::vector<double*> next_blocks;
    if (pose_touched) {
      // Linearise at the first estimates (FEJ): a scratch copy of every block.
      std::vector<std::vector<double>> scratch(touched.size());
      std::unordered_map<double*, double*> to_scratch;
      std::unordered_map<const double*, double*> to_real;
      std::vector<MarginalizationBlock> blocks;
      for (std::size_t i = 0; i < touched.size(); ++i) {
        const BlockKind kind = KindOf(touched[i]);
        const int n = AmbientSize(kind);
        const auto it = fe.find(touched[i]);
        if (opt.first_estimate_jacobians && it != fe.end()) {
          scratch[i] = it->second;
        } else {
          scratch[i].assign(touched[i], touched[i] + n);
        }
        to_scratch[touched[i]] = scratch[i].data();
        to_real[scratch[i].data()] = touched[i];
        blocks.push_back({scratch[i].data(), n, ManifoldOf(kind)});
      }
      std::vector<MarginalizationResidual> mres;
      for (const ResidualSpec& r : residuals) {
        MarginalizationResidual m;
        m.cost = r.cost.get();
        m.loss = r.robust ? loss.get() : nullptr;
        for (double* b : r.blocks) m.blocks.push_back(to_scratch[b]);
        mres.push_back(std::move(m));
      }
      std::vector<double*> mremove;
      for (double* b : remove) mremove.push_back(to_scratch[b]);
      try {
        next = std::make_unique<MarginalizationPrior>(
            MarginalizationPrior::Build(blocks, mres, mremove, opt.marginalization));
        for (const MarginalizationBlock& b : next->KeptBlocks())
          next_blocks.push_back(to_real[b.values]);
      } catch (const std::invalid_argument&) {
        next.reset();
        result->marginalization_failed = true;
      }
    }
    InstallPrior(std::move(next), next_blocks, result);
    retained.erase(std::remove_if(retained.begin(), retained.end(),
                                  [&](const std::unique_ptr<RetainedPose>& rp) {
                                    return std::find(retained_out.begin(), retained_out.end(),
                                                     rp.get()) != retained_out.end();
                                  }),
                   retained.end());
    if (k0_retained) {
      // k0's pose block moves to the retained storage (the prior and FEJ refer to it there).
      std::copy(f0->pose, f0->pose + 7, k0_retained->pose);
      for (double*& b : prior_blocks)
        if (b == f0->pose) b = k0_retained->pose;
      const auto it = fe.find(f0->pose);
      if (it != fe.end()) {
        fe[k0_retained->pose] = it->second;
        fe.erase(f0->pose);
      }
      retained.push_back(std::move(k0_retained));
    }
    DropOldestKeyframe(remove_points, remove_lines, result);
  }

  // After k0 went into the prior: drop it and the landmarks eliminated with it.
  void DropOldestKeyframe(const std::vector<int>& remove_points,
                          const std::vector<int>& remove_lines, FrameResult* result) {
    keyframes.pop_front();
    keyframes.front()->imu_from_previous.reset();
    keyframes.front()->state_prior = false;
    for (int id : remove_points) points.erase(id);
    for (int id : remove_lines) lines.erase(id);
    result->marginalized_keyframes = 1;
    result->marginalized_landmarks = static_cast<int>(remove_points.size() + remove_lines.size());
    RemoveWeakLandmarks();
  }

  // PriorBlocks::kPoses: see the option. Landmarks of k0 whose track has ended are eliminated one
  // by one into small priors on their observers' poses (at the first estimates), then k0's pose
  // is eliminated from those, its pose prior and the previous prior.
  void MarginalizeOldestIntoPoses(FrameResult* result) {
    Frame* f0 = keyframes.front().get();
    const Frame* newest = keyframes.back().get();
    std::set<int> points_newest, lines_newest, points_kept, lines_kept;
    for (std::size_t k = 1; k < keyframes.size(); ++k) {
      const Frame& f = *keyframes[k];
      const bool is_newest = &f == newest;
      for (std::size_t i = 0; i < f.input.points.size(); ++i) {
        if (f.point_outlier[i]) continue;
        points_kept.insert(f.input.points[i].point_id);
        if (is_newest) points_newest.insert(f.input.points[i].point_id);
      }
      for (std::size_t i = 0; i < f.input.segments.size(); ++i) {
        if (f.segment_outlier[i]) continue;
        lines_kept.insert(f.input.segments[i].line_id);
        if (is_newest) lines_newest.insert(f.input.segments[i].line_id);
      }
    }
    // Landmarks leaving the window: observed by no remaining keyframe, or by k0 and no longer
    // tracked by the newest keyframe.
    std::set<const double*> leaving;
    std::vector<int> remove_points, remove_lines, retire_point, retire_line;
    for (std::size_t i = 0; i < f0->input.points.size(); ++i) {
      const int id = f0->input.points[i].point_id;
      if (f0->point_outlier[i] || !points.count(id)) continue;
      if (points_newest.count(id)) {
        ++result->dropped_point_observations;
      } else {
        leaving.insert(points[id]->p);
        retire_point.push_back(id);
      }
    }
    for (std::size_t i = 0; i < f0->input.segments.size(); ++i) {
      const int id = f0->input.segments[i].line_id;
      if (f0->segment_outlier[i] || !lines.count(id)) continue;
      if (lines_newest.count(id) || !opt.keep_marginalized_lines) {
        ++result->dropped_line_observations;
      } else {
        leaving.insert(lines[id]->block);
        retire_line.push_back(id);
      }
    }
    for (const auto& [id, p] : points)
      if (!points_kept.count(id) || leaving.count(p->p)) remove_points.push_back(id);
    for (const auto& [id, l] : lines)
      if (!lines_kept.count(id) || leaving.count(l->block)) remove_lines.push_back(id);

    // Every window residual of the leaving landmarks, grouped by landmark.
    std::vector<ResidualSpec> all;
    for (auto& f : keyframes) AppendFrameResiduals(f.get(), true, opt.use_lines, &all);
    UseExtrinsicBlock(&all);  // the landmark is the last block
    // In the order of first observation (not of the addresses: the run is deterministic).
    std::vector<std::pair<const double*, std::vector<ResidualSpec*>>> by_landmark;
    std::map<const double*, std::size_t> landmark_index;
    for (ResidualSpec& r : all) {
      if (r.frame == nullptr || !leaving.count(r.blocks.back())) continue;
      std::vector<const double*> params(r.blocks.begin(), r.blocks.end());
      double res[2];
      if (!r.cost->Evaluate(params.data(), res, nullptr)) continue;
      const auto [it, added] = landmark_index.emplace(r.blocks.back(), by_landmark.size());
      if (added) by_landmark.push_back({r.blocks.back(), {}});
      by_landmark[it->second].second.push_back(&r);
    }
    // Scratch copies of the keyframe blocks (poses; velocities and biases in the inertial mode)
    // at their first estimates (FEJ), else their current values.
    std::map<double*, std::vector<double>> scratch;
    std::map<double*, BlockKind> scratch_kind;
    auto scratch_of = [&](double* block) {
      auto it = scratch.find(block);
      if (it != scratch.end()) return it->second.data();
      const BlockKind kind = KindOf(block);
      const auto fe_it = fe.find(block);
      std::vector<double> v = opt.first_estimate_jacobians && fe_it != fe.end()
                                  ? fe_it->second
                                  : std::vector<double>(block, block + AmbientSize(kind));
      scratch_kind[block] = kind;
      return scratch.emplace(block, std::move(v)).first->second.data();
    };
    std::map<const double*, double*> to_real;
    std::vector<std::unique_ptr<MarginalizationPrior>> landmark_priors;
    for (auto& [landmark, list] : by_landmark) {
      const BlockKind kind = KindOf(landmark);
      const int n = AmbientSize(kind);
      std::vector<double> lm(landmark, landmark + n);
      std::vector<MarginalizationBlock> blocks = {{lm.data(), n, ManifoldOf(kind)}};
      std::vector<MarginalizationResidual> mres;
      for (ResidualSpec* r : list) {
        MarginalizationResidual m{r->cost.get(), loss.get(), {}};
        for (std::size_t b = 0; b + 1 < r->blocks.size(); ++b) {  // the pose (and extrinsic)
          double* pose = scratch_of(r->blocks[b]);
          to_real[pose] = r->blocks[b];
          if (std::none_of(blocks.begin(), blocks.end(),
                           [&](const MarginalizationBlock& x) { return x.values == pose; }))
            blocks.push_back({pose, 7, &pose_manifold});
          m.blocks.push_back(pose);
        }
        m.blocks.push_back(lm.data());
        mres.push_back(std::move(m));
      }
      try {
        auto p = std::make_unique<MarginalizationPrior>(
            MarginalizationPrior::Build(blocks, mres, {lm.data()}, opt.marginalization));
        if (p->Statistics().prior_rank > 0) landmark_priors.push_back(std::move(p));
      } catch (const std::invalid_argument&) {
        // Its information is lost; the landmark leaves anyway.
      }
    }
    // k0's pose out of the landmark priors, its pose prior and the previous prior.
    std::vector<std::unique_ptr<ceres::CostFunction>> costs;
    std::vector<MarginalizationResidual> mres;
    for (const auto& p : landmark_priors) {
      costs.emplace_back(p->CreateCostFunction());
      MarginalizationResidual m{costs.back().get(), nullptr, {}};
      for (const MarginalizationBlock& b : p->KeptBlocks()) m.blocks.push_back(b.values);
      mres.push_back(std::move(m));
    }
    // k0's pose prior; inertial: its state priors and the IMU (and zero-motion) factor to its
    // successor, so that the successor's pose, velocity and bias keep what they said.
    std::vector<ResidualSpec> own;
    AppendFrameResiduals(f0, false, false, &own);
    if (opt.inertial) {
      AppendInertialResiduals(0, &own);
      AppendInertialResiduals(1, &own);
    }
    if (prior) {
      ResidualSpec r;
      r.cost.reset(prior->CreateCostFunction());
      r.blocks = prior_blocks;
      own.push_back(std::move(r));
    }
    for (ResidualSpec& r : own) {
      MarginalizationResidual m{r.cost.get(), nullptr, {}};
      for (double* b : r.blocks) {
        double* s = scratch_of(b);
        to_real[s] = b;
        m.blocks.push_back(s);
      }
      mres.push_back(std::move(m));
    }
    std::vector<MarginalizationBlock> blocks;
    for (const auto& f : keyframes) {  // oldest first (deterministic order)
      for (double* real : {f->pose, f->v, f->bias}) {
        if (!scratch.count(real)) continue;
        const BlockKind kind = scratch_kind.at(real);
        blocks.push_back({scratch.at(real).data(), AmbientSize(kind), ManifoldOf(kind)});
      }
    }
    if (scratch.count(extrinsic))
      blocks.push_back({scratch.at(extrinsic).data(), 7, &pose_manifold});
    std::unique_ptr<MarginalizationPrior> next;
    std::vector<double*> next_blocks;
    // k0's blocks that a residual touches are removed. Only k0 touched (e.g. every leaving
    // landmark was seen by k0 alone): nothing remains for a prior to constrain.
    std::vector<double*> f0_scratch;
    for (double* b : {f0->pose, f0->v, f0->bias})
      if (scratch.count(b)) f0_scratch.push_back(scratch.at(b).data());
    const bool others =
        std::any_of(mres.begin(), mres.end(), [&](const MarginalizationResidual& m) {
          return std::any_of(m.blocks.begin(), m.blocks.end(), [&](double* b) {
            return std::find(f0_scratch.begin(), f0_scratch.end(), b) == f0_scratch.end();
          });
        });
    if (!f0_scratch.empty() && others) {
      try {
        next = std::make_unique<MarginalizationPrior>(
            MarginalizationPrior::Build(blocks, mres, f0_scratch, opt.marginalization));
        for (const MarginalizationBlock& b : next->KeptBlocks())
          next_blocks.push_back(to_real.at(b.values));
      } catch (const std::invalid_argument&) {
        next.reset();
        result->marginalization_failed = true;
      }
    }
    InstallPrior(std::move(next), next_blocks, result);
    ConsumeTracks(retire_point, retire_line);
    DropOldestKeyframe(remove_points, remove_lines, result);
  }

  // The tracks whose landmark went into a poses-only prior with all its window observations:
  // retired (never triangulated again), or with retire_marginalized_tracks = false those
  // observations are marked used (outliers) so that the track can start a new landmark from
  // later keyframes only (a revisited scene point of a features folder, whose ids are scene ids)
  // without counting them twice.
  void ConsumeTracks(const std::vector<int>& point_ids, const std::vector<int>& line_ids) {
    if (opt.retire_marginalized_tracks) {
      retired_points.insert(point_ids.begin(), point_ids.end());
      retired_lines.insert(line_ids.begin(), line_ids.end());
      return;
    }
    const std::set<int> pset(point_ids.begin(), point_ids.end());
    const std::set<int> lset(line_ids.begin(), line_ids.end());
    for (auto& f : keyframes) {
      for (std::size_t i = 0; i < f->input.points.size(); ++i)
        if (pset.count(f->input.points[i].point_id)) f->point_outlier[i] = 1;
      for (std::size_t i = 0; i < f->input.segments.size(); ++i)
        if (lset.count(f->input.segments[i].line_id)) f->segment_outlier[i] = 1;
    }
  }

  // The new prior and its first estimates (none if empty).
  void InstallPrior(std::unique_ptr<MarginalizationPrior> next,
                    const std::vector<double*>& next_blocks, FrameResult* result) {
    fe.clear();
    prior = std::move(next);
    prior_blocks = next_blocks;
    prior_lines = 0;
    if (!prior) return;
    result->prior_rank = prior->Statistics().prior_rank;
    result->prior_dimension = prior->Statistics().kept_dimension;
    for (std::size_t i = 0; i < prior_blocks.size(); ++i) {
      const BlockKind kind = KindOf(prior_blocks[i]);
      if (opt.first_estimate_landmarks || (kind != BlockKind::kPoint && kind != BlockKind::kLine))
        fe[prior_blocks[i]] = prior->LinearisationPoint()[i];
    }
    if (prior->Statistics().prior_rank == 0) {
      prior.reset();
      prior_blocks.clear();
      fe.clear();
    }
    prior_lines = static_cast<int>(
        std::count_if(prior_blocks.begin(), prior_blocks.end(),
                      [this](const double* b) { return KindOf(b) == BlockKind::kLine; }));
  }

  void Clear() {
    keyframes.clear();
    points.clear();
    lines.clear();
    prior.reset();
    prior_blocks.clear();
    fe.clear();
    retired_points.clear();
    retired_lines.clear();
    retained.clear();
    ResetExtrinsic();
    prior_lines = 0;
  }

  // The tail of both initialisations: the two keyframes are in place.
  InitializationResult StartWindow(int min_landmarks) {
    InitializationResult result;
    // Newest first; with two keyframes only the newest finds tracks seen twice.
    for (auto it = keyframes.rbegin(); it != keyframes.rend(); ++it)
      Triangulate(**it, &result.points, &result.lines);
    if (result.points + result.lines < min_landmarks) {
      Clear();
      return result;
    }
    FrameResult solve;
    SolveWindow(&solve);
    result.iterations = solve.window_iterations;
    result.final_cost = solve.final_cost;
    result.residuals = solve.residuals;
    result.points = static_cast<int>(points.size());
    result.lines = static_cast<int>(lines.size());
    result.T_w_a = keyframes.front()->T_w_c();
    result.T_w_b = keyframes.back()->T_w_c();
    result.ok = result.points + result.lines >= min_landmarks;
    if (!result.ok) {
      Clear();
      return result;
    }
    prev_T_w_c = keyframes[keyframes.size() - 2]->T_w_c();
    last_T_w_c = result.T_w_b;
    return result;
  }

  void FillCounts(FrameResult* r) const {
    r->window_points = static_cast<int>(points.size());
    r->window_lines = static_cast<int>(lines.size());
    r->window_keyframes = static_cast<int>(keyframes.size());
    r->retained_poses = static_cast<int>(retained.size());
    r->prior_lines = prior_lines;
  }
};

SlidingWindowEstimator::SlidingWindowEstimator(const PinholeIntrinsics& K,
                                               const SlidingWindowOptions& options)
    : impl_(std::make_unique<Impl>()) {
  if (!K.IsValid()) throw std::invalid_argument("SlidingWindowEstimator: invalid intrinsics");
  if (options.window_size < 2)
    throw std::invalid_argument("SlidingWindowEstimator: window_size < 2");
  if (!(options.point_sigma_px > 0.0) || !(options.line_sigma_px > 0.0) ||
      !(options.loss_scale > 0.0))
    throw std::invalid_argument("SlidingWindowEstimator: sigmas and loss scale must be positive");
  if (!(options.max_keyframe_interval_s >= 0.0))
    throw std::invalid_argument("SlidingWindowEstimator: max_keyframe_interval_s < 0");
  impl_->K = K;
  impl_->opt = options;
  if (options.loss == LossKind::kHuber)
    impl_->loss = std::make_unique<ceres::HuberLoss>(options.loss_scale);
  if (options.loss == LossKind::kCauchy)
    impl_->loss = std::make_unique<ceres::CauchyLoss>(options.loss_scale);
  if (options.inertial && options.inertial->estimate_extrinsic &&
      !(options.inertial->extrinsic_rotation_sigma > 0.0 &&
        options.inertial->extrinsic_translation_sigma > 0.0 &&
        options.inertial->extrinsic_min_rotation_deg >= 0.0)) {
    throw std::invalid_argument(
        "SlidingWindowEstimator: the extrinsic sigmas must be positive and "
        "extrinsic_min_rotation_deg >= 0");
  }
  if (options.inertial && !(options.inertial->tracking_velocity_sigma >= 0.0 &&
                            std::isfinite(options.inertial->tracking_velocity_sigma))) {
    throw std::invalid_argument("SlidingWindowEstimator: tracking_velocity_sigma must be >= 0");
  }
  impl_->ResetExtrinsic();
}

SlidingWindowEstimator::~SlidingWindowEstimator() = default;

bool SlidingWindowEstimator::initialized() const { return !impl_->keyframes.empty(); }

InitializationResult SlidingWindowEstimator::Initialize(const FrameInput& a, const SE3d& T_w_a,
                                                        const FrameInput& b, const SE3d& T_w_b,
                                                        int min_landmarks) {
  Impl& m = *impl_;
  m.Clear();
  m.keyframes.push_back(m.MakeFrame(a, T_w_a));
  m.keyframes.push_back(m.MakeFrame(b, T_w_b));
  return m.StartWindow(min_landmarks);
}

InitializationResult SlidingWindowEstimator::Initialize(const std::vector<FrameInput>& frames,
                                                        const std::vector<SE3d>& T_w_c,
                                                        int min_landmarks) {
  Impl& m = *impl_;
  if (m.opt.inertial) throw std::logic_error("Initialize: use InitializeInertial (inertial mode)");
  if (frames.size() != T_w_c.size() || frames.size() < 2 ||
      static_cast<int>(frames.size()) > m.opt.window_size) {
    throw std::invalid_argument("Initialize: " + std::to_string(frames.size()) + " frames and " +
                                std::to_string(T_w_c.size()) +
                                " poses (2 to window_size of each needed)");
  }
  m.Clear();
  for (std::size_t k = 0; k < frames.size(); ++k)
    m.keyframes.push_back(m.MakeFrame(frames[k], T_w_c[k]));
  return m.StartWindow(min_landmarks);
}

void SlidingWindowEstimator::AddImu(const std::vector<sensor::ImuSample>& samples) {
  Impl& m = *impl_;
  if (!m.opt.inertial) throw std::logic_error("SlidingWindowEstimator::AddImu: not inertial");
  double last = m.imu.empty() ? -std::numeric_limits<double>::infinity() : m.imu.back().t;
  for (const sensor::ImuSample& s : samples) {
    if (!(s.t > last) || !s.gyro.allFinite() || !s.accel.allFinite()) {
      throw std::invalid_argument(
          "SlidingWindowEstimator::AddImu: IMU samples must be finite with increasing times");
    }
    last = s.t;
  }
  m.imu.insert(m.imu.end(), samples.begin(), samples.end());
}

InitializationResult SlidingWindowEstimator::InitializeInertial(const FrameInput& a,
                                                                const InertialState& state_a,
                                                                const FrameInput& b,
                                                                const InertialState& state_b,
                                                                int min_landmarks) {
  return InitializeInertial(std::vector<FrameInput>{a, b},
                            std::vector<InertialState>{state_a, state_b}, min_landmarks);
}

InitializationResult SlidingWindowEstimator::InitializeInertial(
    const std::vector<FrameInput>& frames, const std::vector<InertialState>& states,
    int min_landmarks) {
  Impl& m = *impl_;
  if (!m.opt.inertial) throw std::logic_error("InitializeInertial: not in the inertial mode");
  if (frames.size() != states.size() || frames.size() < 2 ||
      static_cast<int>(frames.size()) > m.opt.window_size) {
    throw std::invalid_argument("InitializeInertial: " + std::to_string(frames.size()) +
                                " frames and " + std::to_string(states.size()) +
                                " states (2 to window_size of each needed)");
  }
  std::vector<std::unique_ptr<ImuPreintegration>> imu;
  for (std::size_t k = 1; k < frames.size(); ++k) {
    imu.push_back(std::make_unique<ImuPreintegration>(
        m.Preintegrate(frames[k - 1].time, frames[k].time, states[k - 1].bias)));
  }
  m.Clear();
  for (std::size_t k = 0; k < frames.size(); ++k) {
    m.keyframes.push_back(m.MakeFrame(frames[k], states[k].T_w_b * m.T_b_c));
    m.keyframes.back()->SetState(states[k]);
    m.keyframes.back()->input.stationary =
        m.BelievedStationary(frames[k].stationary, states[k].v_w);
    if (k > 0) m.keyframes.back()->imu_from_previous = std::move(imu[k - 1]);
  }
  Frame& fa = *m.keyframes.front();
  fa.state_prior = true;
  std::copy(fa.v, fa.v + 3, fa.v_prior);
  std::copy(fa.bias, fa.bias + 6, fa.bias_prior);
  const InitializationResult result = m.StartWindow(min_landmarks);
  if (result.ok) m.PruneImu();
  return result;
}

SE3d SlidingWindowEstimator::ExtrinsicEstimate() const {
  if (!impl_->opt.inertial) throw std::logic_error("ExtrinsicEstimate: not in the inertial mode");
  return impl_->T_b_c;
}

bool SlidingWindowEstimator::ExtrinsicFree() const { return impl_->extrinsic_free; }

std::vector<InertialState> SlidingWindowEstimator::KeyframeStates() const {
  std::vector<InertialState> out;
  for (const auto& f : impl_->keyframes) out.push_back(f->State());
  return out;
}

FrameResult SlidingWindowEstimator::AddFrame(const FrameInput& input,
                                             const StageObserver& observer) {
  Impl& m = *impl_;
  auto stage = [&observer](WindowStage s) {
    if (observer) observer(s);
  };
  FrameResult result;
  if (m.keyframes.empty())
    throw std::logic_error("SlidingWindowEstimator::AddFrame before Initialize");
  // Predict (inertial mode: the IMU from the newest keyframe; throws before any change when the
  // samples do not cover the frame).
  std::unique_ptr<ImuPreintegration> imu;
  InertialState imu_state;
  if (m.opt.inertial) {
    imu_state = m.Predict(input.time, &imu);
    result.stationary = m.BelievedStationary(input.stationary, m.keyframes.back()->State().v_w);
    if (result.stationary) {  // the body stands: the newest keyframe's pose, zero velocity
      imu_state.T_w_b = m.keyframes.back()->State().T_w_b;
      imu_state.v_w.setZero();
    }
  }
  const SE3d predicted = input.T_w_c_guess ? *input.T_w_c_guess
                         : m.opt.inertial  ? imu_state.T_w_b * m.T_b_c
                                           : m.last_T_w_c * (m.prev_T_w_c.Inverse() * m.last_T_w_c);
  std::unique_ptr<Frame> frame = m.MakeFrame(input, predicted);
  frame->input.stationary = result.stationary;
  stage(WindowStage::kTracking);
  std::unique_ptr<ceres::CostFunction> imu_prior;
  if (m.opt.inertial && m.opt.inertial->tracking_velocity_sigma > 0.0 && !input.T_w_c_guess) {
    imu_prior.reset(m.ImuPosePrior(imu_state, *imu));
  }
  Impl::TrackResult track = m.Track(frame.get(), predicted, imu_prior.get());
  if (!track.ok && m.opt.pnp_fallback) {
    const std::optional<SE3d> pnp = m.PnpPose(*frame);
    result.pnp_fallback = true;
    if (pnp) {
      std::fill(frame->point_outlier.begin(), frame->point_outlier.end(), 0);
      std::fill(frame->segment_outlier.begin(), frame->segment_outlier.end(), 0);
      track = m.Track(frame.get(), *pnp);
    }
  }
  result.tracking_iterations = track.iterations;
  result.tracked_points = track.points;
  result.tracked_lines = track.lines;
  result.ok = track.ok;
  result.T_w_c = track.ok ? track.T_w_c : predicted;
  frame->SetCameraPose(result.T_w_c);
  // Decide.
  result.parallax_px = m.Parallax(*frame);
  const int observed = static_cast<int>(frame->input.points.size() + frame->input.segments.size());
  result.keyframe =
      track.ok && (result.parallax_px >= m.opt.keyframe_parallax_px ||
                   track.points + track.lines < m.opt.min_tracked ||
                   track.points + track.lines < m.opt.min_tracked_ratio * observed ||
                   (m.opt.max_keyframe_interval_s > 0.0 &&
                    input.time - m.keyframes.back()->input.time >= m.opt.max_keyframe_interval_s));
  if (m.opt.inertial) {
    result.imu_only = !track.ok;
    result.keyframe = result.keyframe || input.time - m.keyframes.back()->input.time >=
                                             m.opt.inertial->max_keyframe_interval_s;
    imu_state.T_w_b = SE3d::FromParameters(frame->pose);
    result.state = imu_state;
    frame->SetState(imu_state);
    frame->imu_from_previous = std::move(imu);
  }
  if (result.keyframe) {
    m.keyframes.push_back(std::move(frame));
    stage(WindowStage::kTriangulation);
    m.Triangulate(*m.keyframes.back(), &result.new_points, &result.new_lines);
    stage(WindowStage::kSolve);
    m.SolveWindow(&result);
    result.T_w_c = m.keyframes.back()->T_w_c();
    if (m.opt.inertial) {
      result.state = m.keyframes.back()->State();
      result.imu_chi2 = m.NewestImuChi2();
    }
    if (static_cast<int>(m.keyframes.size()) > m.opt.window_size) {
      stage(WindowStage::kMarginalization);
      if (m.opt.prior_blocks == SlidingWindowOptions::PriorBlocks::kPoses) {
        m.MarginalizeOldestIntoPoses(&result);
      } else {
        m.MarginalizeOldest(&result);
      }
    }
    if (m.opt.inertial) m.PruneImu();
  }
  m.prev_T_w_c = m.last_T_w_c;
  m.last_T_w_c = result.T_w_c;
  result.extrinsic_free = m.extrinsic_free;
  m.FillCounts(&result);
  stage(WindowStage::kDone);
  return result;
}

std::optional<SE3d> SlidingWindowEstimator::Localize(const FrameInput& input,
                                                     const SE3d& guess) const {
  if (impl_->keyframes.empty()) return std::nullopt;
  // MakeFrame only numbers the frame; a local copy of the counter keeps this const.
  Impl& m = *impl_;
  const int saved = m.next_index;
  std::unique_ptr<Frame> frame = m.MakeFrame(input, guess);
  m.next_index = saved;
  const Impl::TrackResult track = m.Track(frame.get(), guess);
  if (!track.ok) return std::nullopt;
  return track.T_w_c;
}

std::optional<Eigen::Matrix<double, 6, 6>> SlidingWindowEstimator::NewestPoseCovariance() const {
  Impl& m = *impl_;
  if (m.keyframes.empty()) return std::nullopt;
  ceres::Problem problem(Impl::ProblemOptions());
  m.BuildProblem(&problem, false);
  double* pose = m.keyframes.back()->pose;
  if (!problem.HasParameterBlock(pose)) return std::nullopt;
  // Inertial: the gauge (position and yaw) held on the oldest keyframe, its roll and pitch free.
  RollPitchPoseManifold roll_pitch;
  if (m.opt.inertial && m.keyframes.size() > 1 &&
      problem.HasParameterBlock(m.keyframes.front()->pose)) {
    problem.SetManifold(m.keyframes.front()->pose, &roll_pitch);
  }
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::SPARSE_QR;  // fails (nullopt) when the information is rank-deficient
  co.apply_loss_function = true;
  ceres::Covariance covariance(co);
  const std::vector<std::pair<const double*, const double*>> blocks = {{pose, pose}};
  if (!covariance.Compute(blocks, &problem)) return std::nullopt;
  Eigen::Matrix<double, 6, 6, Eigen::RowMajor> c;
  if (!covariance.GetCovarianceBlockInTangentSpace(pose, pose, c.data())) return std::nullopt;
  return Eigen::Matrix<double, 6, 6>(c);
}

std::vector<SE3d> SlidingWindowEstimator::KeyframePoses() const {
  std::vector<SE3d> out;
  for (const auto& f : impl_->keyframes) out.push_back(f->T_w_c());
  return out;
}

std::map<int, Eigen::Vector3d> SlidingWindowEstimator::Points() const {
  std::map<int, Eigen::Vector3d> out;
  for (const auto& [id, p] : impl_->points) out[id] = Eigen::Vector3d(p->p[0], p->p[1], p->p[2]);
  return out;
}

std::map<int, Line6d> SlidingWindowEstimator::Lines() const {
  std::map<int, Line6d> out;
  for (const auto& [id, l] : impl_->lines) {
    const Line6d L_a = PluckerFromOrthonormal(OrthonormalLine::FromParameters(l->block));
    const std::optional<Line6d> L_w = NormalizeLineDirection(WorldFromAnchored(L_a, l->anchor));
    if (L_w) out[id] = *L_w;
  }
  return out;
}

}  // namespace window
}  // namespace plucker
