// The outputs of `plucker vo`: --out (the refined view), --out-online, the summary on stderr and
// --json FILE: per frame the refined view's statistics (odometry::MonocularOdometry
// Trajectory()), the online result, the front end's counts and the CPU time of the frame's call by
// stage; a summary with the starts, the counts and the speed (window only, and whole pipeline).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "plucker/odometry/monocular_odometry.h"
#include "stage_clock.h"
#include "vo_config.h"

namespace plucker {
namespace app {

// Stage names of the per-frame CPU times the app measures around the pipeline's calls.
enum VoStage {
  kRead,
  kPoints,
  kDetection,
  kLines,
  kTracking,
  kTriangulation,
  kSolve,
  kMargin,
  kOther
};
constexpr int kNumVoStages = 9;

struct VoFrameLog {
  nlohmann::json frontend;  // images: path, skipped reason, observed counts
  odometry::MonocularStatus online = odometry::MonocularStatus::kInitializing;
  bool online_pose = false;
  double ms[kNumVoStages] = {};  // CPU of the frame's read and call; kOther: the rest of the call
};

// The frame's CPU split: the front end's and window's stages, the rest of the call in kOther.
struct VoFrameClock {
  BasicStageClock<vision::FrontendStage, vision::kNumFrontendStages> frontend;
  BasicStageClock<window::WindowStage, window::kNumWindowStages> window;
  double t0 = ThreadCpuMs();
  void Into(VoFrameLog* f) {
    double staged = 0.0;
    for (int s = 0; s < vision::kNumFrontendStages; ++s)
      staged += f->ms[kPoints + s] = frontend.ms(s);
    for (int s = 0; s < window::kNumWindowStages; ++s)
      staged += f->ms[kTracking + s] = window.ms(s);
    f->ms[kOther] = ThreadCpuMs() - t0 - staged;
  }
};

struct VoRunLog {
  std::vector<VoFrameLog> frames;
  double finish_ms = 0.0;      // CPU of Finish() (a start search at the end of the input)
  double read_ms = 0.0;        // wall time before the loop (features folder, calibration)
  double total_wall_ms = 0.0;  // whole run
  int point_stride = 1;
  int skipped_images = 0;
};

void WriteVoJson(const std::string& path, const odometry::MonocularOdometry& vo,
                 const VoConfig& config, const VoRunLog& log);

struct VoOutputs {
  std::string out, out_online, json;
  std::string source;  // the input, named in errors
  bool quiet = false;
};

// After Finish(): throws io::IoError when there was no start; warns about a failed restart and
// lost frames; writes the files given; prints the summary line unless quiet.
void WriteVoOutputs(const VoOutputs& o, const odometry::MonocularOdometry& vo,
                    const VoConfig& config, const std::vector<std::optional<SE3d>>& online,
                    const VoRunLog& log);

}  // namespace app
}  // namespace plucker
