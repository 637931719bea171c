// The start's test of `plucker vio` (docs/cli.md, exit codes): the window's first solve after the
// start against checks.max_start_imu_chi2 and checks.max_start_culled_share.
#pragma once

#include <nlohmann/json.hpp>

#include "vio_output.h"

namespace plucker {
namespace app {

// The window's first solve after the start (its first keyframe: the start's keyframes, landmarks
// and state under the IMU factors): its newest IMU factor's whitened chi2 and the share of its
// observations culled as outliers, against their bounds (0: off). A start on a wrong scale (a
// vision-only run whose scale drifted, absorbed by the accelerometer bias) shows there
// (docs/results/vio.md, session 22). Not solved before the window's first keyframe. The share
// is of the solve's residual blocks (observations, IMU factors, priors).
struct VioStartBounds {
  double max_imu_chi2 = 0.0, max_culled_share = 0.0;
};
struct VioStartCheck {
  bool solved = false;
  VioReport::KeyframeChi2 keyframe;
  double culled_share = 0.0;
  bool chi2_over = false, culled_over = false;
  bool failed() const { return chi2_over || culled_over; }
};
// The culled share counts only from this many culled observations on (a share of a few is
// noise: 1 of 88 in a 4 s room).
constexpr int kMinStartCulled = 10;
VioStartCheck CheckStart(const VioReport& report, const VioStartBounds& bounds);
// Its JSON (`start_check` of the summary): solved, failed, the bounds and frame, time,
// imu_chi2, culled, residuals, culled_share.
nlohmann::json StartCheckJson(const VioStartCheck& check, const VioStartBounds& bounds);
// Its warning (stderr, --quiet or not) when it failed; returns kExitImuOnly then, else 0.
int WarnStart(const VioStartCheck& check, const VioStartBounds& bounds);

// The distribution of the keyframes' IMU factor chi2 (15 degrees of freedom) for the JSON
// summary (`keyframe_imu_chi2`): median, p95, largest and the share over the chi2 0.99 quantile
// (30.58); zeros without keyframes.
nlohmann::json KeyframeChi2StatsJson(const VioReport& report);

}  // namespace app
}  // namespace plucker
