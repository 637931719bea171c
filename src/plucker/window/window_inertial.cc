// The visual-inertial mode's IMU: the sample buffer, preintegration and prediction from the newest
// keyframe, the inertial residuals (IMU factor, zero motion, first-keyframe priors) and the IMU
// prior of per-frame tracking.
#include <ceres/autodiff_cost_function.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <limits>
#include <stdexcept>

#include "plucker/factors/imu_factor.h"
#include "plucker/window/window_factors_internal.h"
#include "plucker/window/window_internal.h"

namespace plucker {
namespace window {

using internal::PosePriorResidual;
using internal::ResidualSpec;
using internal::VectorPriorResidual;
using internal::ZeroMotionResidual;

// The IMU from time t0 to t1 at the bias `bias` (throws std::invalid_argument when the samples
// do not cover the interval).
ImuPreintegration SlidingWindowEstimator::Impl::Preintegrate(double t0, double t1,
                                                             const sensor::ImuBias& bias) const {
  return PreintegrateSamples(imu, t0, t1, bias, opt.inertial->imu, opt.inertial->imu_gap_s);
}

std::optional<double> SlidingWindowEstimator::Impl::ImuGapStart(double t0, double t1) const {
  for (std::size_t i = 1; i < imu.size() && imu[i - 1].t < t1; ++i) {
    if (imu[i].t > t0 && imu[i].t - imu[i - 1].t > opt.inertial->imu_gap_s) {
      return std::max(imu[i - 1].t, t0);
    }
  }
  return std::nullopt;
}

// The state at time t predicted from the newest keyframe, with the preintegration used.
sensor::BodyState SlidingWindowEstimator::Impl::Predict(
    double t, std::unique_ptr<ImuPreintegration>* preintegration) const {
  const Frame& kf = *keyframes.back();
  *preintegration = std::make_unique<ImuPreintegration>(Preintegrate(kf.input.time, t, kf.Bias()));
  const sensor::BodyState s = kf.State();
  NavState n;
  n.R_w_b = s.T_w_b.RotationMatrix();
  n.p_w = s.T_w_b.translation();
  n.v_w = s.v_w;
  const NavState p = (*preintegration)->Predict(n, s.bias, opt.inertial->gravity_w);
  return {t, SE3d(p.R_w_b, p.p_w), p.v_w, s.bias};
}

// The IMU factor between keyframes k - 1 and k, and the priors of keyframe k.
void SlidingWindowEstimator::Impl::AppendInertialResiduals(std::size_t k,
                                                           std::vector<ResidualSpec>* out) const {
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
void SlidingWindowEstimator::Impl::RepropagateImu() {
  if (!opt.inertial) return;
  for (std::size_t k = 1; k < keyframes.size(); ++k) {
    ImuPreintegration* p = keyframes[k]->imu_from_previous.get();
    if (!p) continue;
    const sensor::ImuBias b = keyframes[k - 1]->Bias();
    if ((b.gyro - p->BiasLinearisation().gyro).norm() > opt.inertial->repropagate_gyro_bias ||
        (b.accel - p->BiasLinearisation().accel).norm() > opt.inertial->repropagate_accel_bias) {
      p->Repropagate(b);
    }
  }
}

// Drops the IMU samples before the newest keyframe (one sample before it is kept).
void SlidingWindowEstimator::Impl::PruneImu() {
  if (keyframes.empty() || imu.size() < 2) return;
  const double t = keyframes.back()->input.time;
  std::size_t keep = 0;
  while (keep + 1 < imu.size() && imu[keep + 1].t <= t) ++keep;
  imu.erase(imu.begin(), imu.begin() + static_cast<std::ptrdiff_t>(keep));
}

// The caller's stationary flag, believed only while the body moves slower than
// InertialOptions::stationary_max_speed (an image test alone takes forward motion for standing).
bool SlidingWindowEstimator::Impl::BelievedStationary(bool flag, const Eigen::Vector3d& v_w) const {
  return flag && v_w.norm() < opt.inertial->stationary_max_speed;
}

// Inertial mode: the prior the IMU prediction puts on a frame's body pose T_w_b (PoseManifold
// tangent: body rotation, world position). Its covariance is the preintegration's from the
// newest keyframe (rotation and position, given the keyframe's state) plus the keyframe's
// velocity uncertainty carried over the time since it, (tracking_velocity_sigma dt)^2 per axis.
ceres::CostFunction* SlidingWindowEstimator::Impl::ImuPosePrior(
    const sensor::BodyState& predicted, const ImuPreintegration& preintegration) const {
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

std::vector<sensor::BodyState> SlidingWindowEstimator::KeyframeStates() const {
  std::vector<sensor::BodyState> out;
  for (const auto& f : impl_->keyframes) out.push_back(f->State());
  return out;
}

}  // namespace window
}  // namespace plucker
