// Does the IMU noise model fit the sensor? Preintegrate the real IMU log over windows that start
// at ground-truth states (pose, velocity, biases), predict the state at the window's end, and
// compare with the ground truth there:
// - prediction errors: position [m], rotation [deg], velocity [m/s];
// - the whitened residual of the IMU factor at the ground-truth states, r^T Sigma^-1 r, against
//   its 15 degrees of freedom (9 preintegrated + 6 bias random walk), and the 9-dimensional
//   preintegration part alone. For a model that fits, the mean is near 15 (9); a much larger
//   mean means the noise figures are optimistic (their square root is roughly the factor by
//   which the densities would have to grow); a much smaller one, pessimistic.
// The ground truth's own errors count against the model too: its quality bounds what this can
// tell (say so when reporting).
//
// Windows start at every `stride`-th ground-truth state whose window end falls within
// `time_tolerance` of another ground-truth state and inside the IMU log; the samples are
// preintegrated by PreintegrateSamples (factors/imu_preintegration.h).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "plucker/sensor/body_state.h"
#include "plucker/sensor/imu.h"

namespace plucker {
namespace eval {

struct ImuConsistencyOptions {
  std::vector<double> window_seconds{0.25, 1.0};
  int stride = 1;
  double time_tolerance = 1e-3;  // s, window end vs the nearest ground-truth state
  Eigen::Vector3d gravity_w{0.0, 0.0, -9.81};
};

struct ImuWindowError {
  double t_start = 0.0, window = 0.0;
  double position_error = 0.0;       // m
  double rotation_error_deg = 0.0;   // deg
  double velocity_error = 0.0;       // m/s
  double chi2 = 0.0;                 // r^T Sigma^-1 r, 15 degrees of freedom
  double chi2_preintegration = 0.0;  // its [R, v, p] part, 9 degrees of freedom
};

struct ImuConsistencySummary {
  double window = 0.0;
  int count = 0;
  double position_rmse = 0.0, position_median = 0.0, position_p95 = 0.0;
  double rotation_median_deg = 0.0, rotation_p95_deg = 0.0;
  double velocity_median = 0.0;
  double chi2_mean = 0.0, chi2_median = 0.0;
  double chi2_preintegration_mean = 0.0;
};

struct ImuConsistencyResult {
  std::vector<ImuWindowError> windows;
  std::vector<ImuConsistencySummary> summaries;  // one per window length
};

// Throws std::invalid_argument for an empty log or ground truth, non-positive windows or stride,
// or invalid noise figures.
ImuConsistencyResult EvaluateImuConsistency(const std::vector<sensor::ImuSample>& imu,
                                            const std::vector<sensor::BodyState>& ground_truth,
                                            const sensor::ImuModel& model,
                                            const ImuConsistencyOptions& options);

}  // namespace eval
}  // namespace plucker
