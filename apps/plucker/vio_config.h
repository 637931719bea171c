// The options of `plucker vio` (docs/vio.md) in one table (vio_config.cc, the mechanism of
// options_table.h): the odometry's (odometry/visual_inertial_odometry.h) and the input's, set
// from --config FILE.yaml and the flags that set the same options; config/vio_default.yaml and
// the table of docs/vio.md come from it (`plucker config vio [--markdown]`). The keys the VIO
// shares with `plucker vo` (use_lines, window.*, points.*, lines.*) are spelled as there.
#pragma once

#include <string>
#include <vector>

#include "options_table.h"
#include "plucker/odometry/visual_inertial_odometry.h"

namespace plucker {
namespace app {

struct VioConfig {
  odometry::VisualInertialOdometryOptions odometry;
  int point_stride = 1;  // features folders: the point tracks whose id is a multiple of this
  // The largest share of the window's frames without a visual update (IMU only) of a run that
  // exits 0 (else exit code 3, docs/cli.md), in [0, 1].
  double max_imu_only_share = 0.2;
  // A keyframe whose newest IMU factor has a whitened squared residual (15 degrees of freedom)
  // above this after its solve is one where the IMU and the vision disagree: named in a warning,
  // counted (JSON `inconsistent_keyframes`), and any makes the exit code 3 (docs/vio.md). 0: off,
  // the default: no bound separates the failures from the healthy runs measured. A start aligned
  // on half the true speed gave 262 (aggressive corridor, 30 Hz, seed 210, 2.5 m), others 52-83
  // (0.89-1.77 m); healthy runs mostly under 3, but the EuRoC V1_01 head 31.8 (across its IMU gap)
  // and a simulated corridor at 10 Hz (seed 200, 0.031 m) 520. The JSON reports every run's
  // largest (`largest_keyframe_imu_chi2`).
  double max_keyframe_imu_chi2 = 0.0;
  // The window's first solve after the start (its first keyframe: the start's keyframes,
  // landmarks and state under the IMU factors) is the start's test: a start on a wrong scale (a
  // vision-only run whose scale drifted, absorbed by the accelerometer bias) shows there as a
  // large whitened chi2 of the newest IMU factor or as many observations culled as outliers.
  // Either over its bound: named in a warning, JSON `start_check`, exit code 3 (docs/results/
  // vio.md, session 22: the failed fast starts chi2 30-262 or share 0.013-0.038, healthy runs of
  // the study at most 19.6 and 0.0055; unseen seeds: 3 of 5 failures, 1 of 67 healthy runs).
  // 0: that bound off.
  double max_start_imu_chi2 = 25.0;
  double max_start_culled_share = 0.01;
  // The T_b_c to use instead of the input's (rig.txt or sensor.yaml): [tx, ty, tz, qx, qy, qz,
  // qw], the camera in the body frame; empty: the input's.
  std::vector<double> T_b_c;
};

const OptionsTable<VioConfig>& VioOptions();

// Reads --config: a YAML map of keys (nested groups or dotted keys). Unknown or renamed keys,
// wrong types, values out of range and invalid YAML are std::runtime_error naming the file and
// the key.
void ApplyVioConfig(const std::string& path, VioConfig* config);
// *T_b_c = the key extrinsic.T_b_c when it is set (else unchanged).
void UseConfigExtrinsic(const VioConfig& config, SE3d* T_b_c);
// The same for YAML text (`name` stands for the file in the messages, e.g. the Python options),
// with CheckVioConfig after it.
void ApplyVioConfigYaml(const std::string& text, const std::string& name, VioConfig* config);
// The checks across keys (init.max_keyframes >= init.min_keyframes, ...) after the file and the
// flags: std::runtime_error naming `name`.
void CheckVioConfig(const VioConfig& config, const std::string& name);

}  // namespace app
}  // namespace plucker
