#include "plucker/eval/imu_consistency.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "plucker/factors/imu_factor.h"
#include "plucker/factors/imu_preintegration.h"
#include "plucker/geometry/so3.h"

namespace plucker {
namespace eval {

namespace {

sensor::ImuBias BiasOf(const sensor::BodyState& s) { return s.bias; }

// Index of the ground-truth state nearest to t, or -1 beyond the tolerance.
int NearestState(const std::vector<sensor::BodyState>& gt, double t, double tolerance) {
  auto it = std::lower_bound(gt.begin(), gt.end(), t,
                             [](const sensor::BodyState& s, double x) { return s.t < x; });
  int best = -1;
  double best_dt = tolerance;
  for (auto c : {it - 1, it}) {
    if (c < gt.begin() || c >= gt.end()) continue;
    const double dt = std::abs(c->t - t);
    if (dt <= best_dt) {
      best_dt = dt;
      best = static_cast<int>(c - gt.begin());
    }
  }
  return best;
}

ImuWindowError Compare(const ImuPreintegration& p, const sensor::BodyState& i,
                       const sensor::BodyState& j, const Eigen::Vector3d& gravity_w) {
  const NavState predicted =
      p.Predict({i.T_w_b.RotationMatrix(), i.T_w_b.translation(), i.v_w}, BiasOf(i), gravity_w);
  ImuWindowError e;
  e.t_start = i.t;
  e.window = p.Dt();
  e.position_error = (predicted.p_w - j.T_w_b.translation()).norm();
  e.velocity_error = (predicted.v_w - j.v_w).norm();
  e.rotation_error_deg =
      LogSO3<double>(Eigen::Quaterniond(j.T_w_b.RotationMatrix().transpose() * predicted.R_w_b))
          .norm() *
      180.0 / M_PI;
  // The factor's residual at the ground-truth states (the value the factor evaluates), whitened
  // by its joint covariance (15 dof) and, for the [R, v, p] part, by the preintegration's own.
  const ImuMeasurement m = MakeImuMeasurement(p, gravity_w);
  Eigen::Matrix<double, 6, 1> bias_i, bias_j;
  bias_i << i.bias.gyro, i.bias.accel;
  bias_j << j.bias.gyro, j.bias.accel;
  const Eigen::Matrix<double, 15, 1> r = ImuResidualT<double>(
      m, i.T_w_b, i.v_w.data(), bias_i.data(), j.T_w_b, j.v_w.data(), bias_j.data());
  e.chi2 = (m.sqrt_information * r).squaredNorm();
  e.chi2_preintegration = r.head<9>().dot(p.Covariance().ldlt().solve(r.head<9>()));
  return e;
}

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

ImuConsistencySummary Summarise(double window, const std::vector<ImuWindowError>& all) {
  ImuConsistencySummary s;
  s.window = window;
  std::vector<double> pos, rot, vel, chi2;
  double sum_sq = 0.0, chi2_sum = 0.0, chi2_pre_sum = 0.0;
  for (const ImuWindowError& e : all) {
    if (e.window != window || !std::isfinite(e.chi2)) continue;
    pos.push_back(e.position_error);
    rot.push_back(e.rotation_error_deg);
    vel.push_back(e.velocity_error);
    chi2.push_back(e.chi2);
    sum_sq += e.position_error * e.position_error;
    chi2_sum += e.chi2;
    chi2_pre_sum += e.chi2_preintegration;
  }
  s.count = static_cast<int>(pos.size());
  if (s.count == 0) return s;
  s.position_rmse = std::sqrt(sum_sq / s.count);
  s.position_median = Quantile(pos, 0.5);
  s.position_p95 = Quantile(pos, 0.95);
  s.rotation_median_deg = Quantile(rot, 0.5);
  s.rotation_p95_deg = Quantile(rot, 0.95);
  s.velocity_median = Quantile(vel, 0.5);
  s.chi2_mean = chi2_sum / s.count;
  s.chi2_median = Quantile(chi2, 0.5);
  s.chi2_preintegration_mean = chi2_pre_sum / s.count;
  return s;
}

}  // namespace

ImuConsistencyResult EvaluateImuConsistency(const std::vector<sensor::ImuSample>& imu,
                                            const std::vector<sensor::BodyState>& gt,
                                            const sensor::ImuModel& model,
                                            const ImuConsistencyOptions& o) {
  if (imu.size() < 2) throw std::invalid_argument("IMU consistency: fewer than 2 IMU samples");
  if (gt.size() < 2)
    throw std::invalid_argument("IMU consistency: fewer than 2 ground-truth states");
  if (o.stride < 1) throw std::invalid_argument("IMU consistency: stride must be >= 1");
  ImuConsistencyResult result;
  for (double window : o.window_seconds) {
    if (!(window > 0.0) || !std::isfinite(window)) {
      throw std::invalid_argument("IMU consistency: windows must be positive");
    }
    // Keep the requested length as the window label (the integrated Dt may differ by rounding).
    for (std::size_t a = 0; a < gt.size(); a += static_cast<std::size_t>(o.stride)) {
      const int b = NearestState(gt, gt[a].t + window, o.time_tolerance);
      if (b < 0) continue;
      if (gt[a].t < imu.front().t || gt[b].t > imu.back().t) continue;
      const ImuPreintegration p = PreintegrateSamples(imu, gt[a].t, gt[b].t, BiasOf(gt[a]), model);
      ImuWindowError e = Compare(p, gt[a], gt[b], o.gravity_w);
      e.window = window;
      result.windows.push_back(e);
    }
    result.summaries.push_back(Summarise(window, result.windows));
  }
  return result;
}

}  // namespace eval
}  // namespace plucker
