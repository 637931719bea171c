// The app's clocks (the libraries read none): per-stage times of an algorithm taken through its
// stage observer (LiDAR odometry, VO window, image front end).
#pragma once

#include <array>
#include <chrono>
#include <ctime>
#include <functional>

#include "plucker/lidar/odometry.h"

namespace plucker {
namespace app {

// CPU time consumed by the calling thread, in milliseconds (robust to a loaded machine).
inline double ThreadCpuMs() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

inline double WallMs() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// Milliseconds per stage of one frame of an algorithm that announces its stages to an observer
// (the LiDAR odometry, the VO window, the image front end; each ends with Stage::kDone): CPU time
// of the calling thread, or wall-clock when the work is spread over threads. Stages visited
// several times (e.g. correspondences and solve, once per association round) add up.
template <typename Stage, int kStages>
class BasicStageClock {
 public:
  explicit BasicStageClock(bool wall = false) : wall_(wall) {}

  // Pass to the algorithm; the times of the frame are read after it returns.
  std::function<void(Stage)> Observer() {
    ms_.fill(0.0);
    current_ = -1;
    return [this](Stage stage) {
      const double now = wall_ ? WallMs() : ThreadCpuMs();
      if (current_ >= 0) ms_[current_] += now - last_;
      current_ = stage == Stage::kDone ? -1 : static_cast<int>(stage);
      last_ = now;
    };
  }
  double ms(Stage stage) const { return ms_[static_cast<int>(stage)]; }
  double ms(int stage) const { return ms_[stage]; }

 private:
  bool wall_;
  std::array<double, kStages> ms_{};
  int current_ = -1;
  double last_ = 0.0;
};

using StageClock = BasicStageClock<lidar::Stage, lidar::kNumStages>;

// The names of the LiDAR odometry's stages in the JSON and tables (`plucker lidar`,
// `plucker bench lidar`), index = lidar::Stage. The image pipelines' are in pipeline_json.h.
inline constexpr std::array<const char*, lidar::kNumStages> kLidarStageNames = {
    "rings", "features", "correspondences", "solve", "map_update"};
inline constexpr const char* kLidarReadStageName = "read";  // reading the scan

}  // namespace app
}  // namespace plucker
