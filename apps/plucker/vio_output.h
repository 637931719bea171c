// The writers of `plucker vio` (docs/vio.md): the report of a run accumulated from the
// odometry's per-frame results (JSON statistics and summary), the two TUM trajectories and
// the plot.
#pragma once

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "plucker/odometry/visual_inertial_odometry.h"
#include "vio_input.h"

namespace plucker {
namespace app {

class VioReport {
 public:
  // The front end's record of frame `frame` (EuRoC): image, stage times, observations.
  void AddFrontend(int frame, nlohmann::json info);
  // A call's result; window_ms: its window stage times, cpu_ms its CPU time, of which
  // frontend_ms in reading the image and the front end's stages.
  void Add(const odometry::VioFrameResult& r,
           const std::array<double, window::kNumWindowStages>& window_ms, double cpu_ms,
           double frontend_ms = 0.0);
  // The JSON of the run (frames, initialisation, summary).
  nlohmann::json Json(const VioInput& in, const odometry::VisualInertialOdometry& vio,
                      double read_ms, double total_wall_ms) const;

  int frames = 0, keyframes = 2, imu_only = 0, stationary = 0, skipped = 0;
  int skipped_images = 0;  // unreadable, blank or of another size: never given to the odometry
  double cpu_ms = 0.0, frontend_ms = 0.0, init_ms = 0.0, frame_ms = 0.0;
  int window_points = 0, window_lines = 0;
  bool extrinsic_estimated = false;
  // Every keyframe the window solved (frame, time, its newest IMU factor's whitened chi2, the
  // observations its solve culled as outliers among its residual blocks), in order.
  struct KeyframeChi2 {
    int frame = 0;
    double time = 0.0, chi2 = 0.0;
    int culled = 0, residuals = 0;
  };
  std::vector<KeyframeChi2> keyframe_chi2;

 private:
  std::vector<nlohmann::json> per_frame_;
  std::vector<double> times_;
  int marginalized_ = 0, failed_marginalizations_ = 0, window_frames_ = 0;
  double chi2_total_ = 0.0;
  std::array<double, window::kNumWindowStages> stage_total_{};
  std::vector<nlohmann::json> frontend_;
  std::vector<double> call_ms_;  // each call's odometry CPU (without the front end), in order
};

// The run's summary on stderr (frames, start, keyframes, CPU against the data's duration; the
// extrinsic's change when estimated).
void PrintVioSummary(const std::string& out, bool estimate_extrinsic, const VioReport& report,
                     const odometry::VisualInertialOdometry& vio, const VioInput& in,
                     double duration);

// Exit code of `plucker vio` when more than max_imu_only_share of the window's frames had no
// visual update (docs/cli.md).
constexpr int kExitImuOnly = 3;
// An IMU-only stretch at least this long is named in a warning, whatever the share.
constexpr double kLongImuOnlyStretchS = 1.0;

// The warnings on frames without a visual update (stderr, --quiet or not): the long stretches
// with their frame ranges, and the share when over max_share; returns kExitImuOnly then, else 0.
int WarnImuOnly(const odometry::VioStatistics& stats, double max_share);

// The keyframes whose IMU factor's whitened chi2 exceeds max_chi2 (the IMU and the vision
// disagree: a start aligned on a wrong scale, a diverged window; none when max_chi2 is 0, off):
// a warning naming them (stderr, --quiet or not); returns kExitImuOnly when there is one, else 0.
std::vector<VioReport::KeyframeChi2> InconsistentKeyframes(const VioReport& report,
                                                           double max_chi2);
int WarnInconsistent(const std::vector<VioReport::KeyframeChi2>& inconsistent, double max_chi2);

// The refined trajectory (`--out`) or the online poses (`--out-online`) as TUM, with a comment
// saying which; on the dataset's clock when the input has one (EuRoC: the stamps of its files,
// io::WriteTumTrajectoryOnClock); returns the frames written.
std::vector<int> WriteVioTrajectory(const std::string& path,
                                    const std::vector<odometry::VioFrameRecord>& records,
                                    bool online, std::optional<std::int64_t> clock_origin_ns);

// Top view of the refined trajectory and its position error (against the ground truth when the
// input has it, aligned in position and yaw), under it its height and the online estimate's IMU
// biases per frame against time (against the ground truth's: EuRoC), in one SVG. records: the
// refined trajectory; online: the per-frame records with their window results (the biases).
void WriteVioPlot(const std::string& path, const VioInput& in,
                  const std::vector<odometry::VioFrameRecord>& records,
                  const std::vector<odometry::VioFrameRecord>& online);

}  // namespace app
}  // namespace plucker
