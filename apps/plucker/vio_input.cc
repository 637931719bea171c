#include "vio_input.h"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "plucker/io/euroc_dataset.h"
#include "plucker/io/io_error.h"
#include "plucker/io/sim_format.h"
#include "plucker/sensor/fisheye_rig.h"

namespace plucker {
namespace app {

std::vector<std::string> SkipWarnings(const std::vector<io::FrameSkip>& skipped,
                                      const std::string& suffix, bool frame_numbers) {
  const std::string at = frame_numbers ? " frame " : ":";
  std::vector<std::string> out;
  for (std::size_t i = 0; i < skipped.size();) {
    std::size_t j = i + 1;
    while (j < skipped.size() && skipped[j].file == skipped[i].file &&
           skipped[j].reason == skipped[i].reason && skipped[j].line == skipped[j - 1].line + 1) {
      ++j;
    }
    if (j == i + 1) {
      const io::FrameSkip& a = skipped[i];
      out.push_back("skipped " + a.file + at + std::to_string(a.line) + ": " + a.reason + suffix);
    } else {
      const io::FrameSkip &a = skipped[i], &b = skipped[j - 1];
      std::ostringstream w;
      w << "skipped " << j - i << " frames, " << a.file << (frame_numbers ? " frames " : ":")
        << a.line << "-" << b.line;
      if (std::isfinite(a.t) && std::isfinite(b.t)) {
        w << std::fixed << std::setprecision(3) << " (times " << a.t << "-" << b.t << " s)";
      }
      w << ": " << a.reason << suffix;
      out.push_back(w.str());
    }
    i = j;
  }
  return out;
}

std::vector<window::FrameInput> FeatureFrames(const sensor::CameraImuSequence& seq, int stride) {
  std::vector<window::FrameInput> frames(seq.frame_times.size());
  for (std::size_t i = 0; i < frames.size(); ++i) frames[i].time = seq.frame_times[i];
  for (const auto& p : seq.points)
    if (p.point_id >= 0 && p.point_id % stride == 0) frames[p.frame].points.push_back(p);
  for (const auto& s : seq.segments) frames[s.frame].segments.push_back(s);
  return frames;
}

VioInput ReadVioFeatures(const std::string& dir, int point_stride) {
  sensor::CameraImuSequence seq = io::ReadCameraImuSequence(dir);
  sensor::ToPinholeView(&seq);  // a fisheye rig's raw points into its view (fisheye_rig.h)
  VioInput in;
  in.source = dir;
  in.calibration.camera.K = seq.rig.K;
  in.calibration.camera.width = seq.rig.width;
  in.calibration.camera.height = seq.rig.height;
  in.calibration.T_b_c = seq.rig.T_b_c;
  in.calibration.imu = seq.imu_model;
  in.calibration.gravity_magnitude = seq.gravity_w.norm();
  in.calibration.pixel_sigma = seq.observation_model.pixel_sigma;
  in.imu = seq.imu;
  if (in.imu.empty()) throw io::IoError(dir + "/imu.txt", "no IMU samples");
  std::vector<window::FrameInput> frames = FeatureFrames(seq, point_stride);
  // The IMU's coverage of each frame (gaps, before the first or after the last sample): frames
  // not covered are skipped and named (the EuRoC reader's check; `line` holds the frame number).
  std::vector<io::EurocFrame> covered;
  for (std::size_t i = 0; i < frames.size(); ++i)
    covered.push_back({frames[i].time, "", static_cast<int>(i)});
  std::vector<io::FrameSkip> skipped;
  std::vector<std::string> warnings;
  io::CheckImuCoverage(in.imu, {}, dir + "/frames.txt", dir + "/imu.txt", &covered, &skipped,
                       &warnings);
  for (io::FrameSkip& s : skipped) s.t = frames[s.line].time;
  for (std::string& w : SkipWarnings(skipped, "", true)) in.warnings.push_back(std::move(w));
  in.skipped_input_frames = static_cast<int>(skipped.size());
  in.warnings.insert(in.warnings.end(), warnings.begin(), warnings.end());
  for (const io::EurocFrame& f : covered) {
    in.frames.push_back(std::move(frames[f.line]));
    if (seq.ground_truth) {
      if (!in.gt_T_w_b) in.gt_T_w_b.emplace();
      in.gt_T_w_b->push_back(seq.ground_truth->T_w_b[f.line]);
    }
  }
  return in;
}

VioInput ReadVioEuroc(const std::string& dir) {
  io::EurocDataset data = io::ReadEurocDataset(dir);
  VioInput in;
  in.source = dir;
  in.clock_origin_ns = data.imu.origin_ns;
  in.calibration.camera = data.cam0.camera;
  in.calibration.T_b_c = data.cam0.T_b_c;
  in.calibration.imu = data.imu.imu_model;
  in.imu = std::move(data.imu.imu);
  in.images = std::move(data.frames);
  in.gt_states = std::move(data.imu.ground_truth);
  for (std::string& w : SkipWarnings(data.skipped)) in.warnings.push_back(std::move(w));
  in.skipped_input_frames = static_cast<int>(data.skipped.size());
  in.warnings.insert(in.warnings.end(), data.warnings.begin(), data.warnings.end());
  return in;
}

std::vector<sensor::BodyState> NearestGroundTruthStates(const VioInput& in,
                                                        const std::vector<double>& times) {
  std::vector<sensor::BodyState> gt;
  const std::vector<sensor::BodyState>& s = in.gt_states;
  std::size_t k = 0;
  for (const double t : times) {
    if (s.empty()) break;
    while (k + 1 < s.size() && std::abs(s[k + 1].t - t) <= std::abs(s[k].t - t)) ++k;
    gt.push_back(s[k]);
  }
  return gt;
}

std::vector<SE3d> NearestGroundTruth(const VioInput& in, const std::vector<double>& times) {
  std::vector<SE3d> gt;
  for (const sensor::BodyState& s : NearestGroundTruthStates(in, times)) gt.push_back(s.T_w_b);
  return gt;
}

}  // namespace app
}  // namespace plucker
