// The app's clocks for timing the LiDAR odometry (the library reads none): per-stage times of
// LidarOdometry::ProcessScan taken through its StageObserver.
#pragma once

#include <array>
#include <chrono>
#include <ctime>

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

// Milliseconds per stage of one frame: CPU time of the calling thread when the odometry runs on
// one thread, wall-clock when it runs on several (the work is spread over threads). Stages
// visited several times (correspondences and solve, once per association round) add up.
class StageClock {
 public:
  explicit StageClock(bool wall) : wall_(wall) {}

  // Pass to ProcessScan; the times of the frame are read after it returns.
  lidar::StageObserver Observer() {
    ms_.fill(0.0);
    current_ = -1;
    return [this](lidar::Stage stage) {
      const double now = wall_ ? WallMs() : ThreadCpuMs();
      if (current_ >= 0) ms_[current_] += now - last_;
      current_ = stage == lidar::Stage::kDone ? -1 : static_cast<int>(stage);
      last_ = now;
    };
  }
  double ms(lidar::Stage stage) const { return ms_[static_cast<int>(stage)]; }

 private:
  bool wall_;
  std::array<double, lidar::kNumStages> ms_{};
  int current_ = -1;
  double last_ = 0.0;
};

}  // namespace app
}  // namespace plucker
