#include "vio_input.h"

#include <array>
#include <iostream>

#include "plucker/io/euroc_dataset.h"
#include "plucker/io/image_folder.h"
#include "plucker/io/io_error.h"
#include "plucker/io/sim_format.h"
#include "plucker/vision/image_frontend.h"
#include "plucker/vision/undistort.h"
#include "stage_clock.h"

namespace plucker {
namespace app {

VioInput ReadVioFeatures(const std::string& dir, int point_stride) {
  const sensor::CameraImuSequence seq = io::ReadCameraImuSequence(dir);
  VioInput in;
  in.source = dir;
  in.K = seq.rig.K;
  in.T_b_c = seq.rig.T_b_c;
  in.imu_model = seq.imu_model;
  in.gravity_magnitude = seq.gravity_w.norm();
  in.pixel_sigma = seq.observation_model.pixel_sigma;
  in.imu = seq.imu;
  if (in.imu.empty()) throw io::IoError(dir + "/imu.txt", "no IMU samples");
  std::vector<window::FrameInput> frames(seq.frame_times.size());
  for (std::size_t i = 0; i < frames.size(); ++i) frames[i].time = seq.frame_times[i];
  for (const auto& p : seq.points)
    if (p.point_id >= 0 && p.point_id % point_stride == 0) frames[p.frame].points.push_back(p);
  for (const auto& s : seq.segments) frames[s.frame].segments.push_back(s);
  // The IMU's coverage of each frame (gaps, before the first or after the last sample): frames
  // not covered are skipped and named (the EuRoC reader's check; its rows are frame numbers).
  std::vector<io::EurocFrame> covered;
  for (std::size_t i = 0; i < frames.size(); ++i)
    covered.push_back({frames[i].time, "", static_cast<int>(i)});
  std::vector<std::string> skipped, warnings;
  io::CheckImuCoverage(in.imu, {}, dir + "/frames.txt", &covered, &skipped, &warnings);
  for (std::string s : skipped) {  // "DIR/frames.txt:I: problem", I the frame number
    s.insert(dir.size() + 11, " frame");
    s[dir.size() + 17] = ' ';
    in.warnings.push_back("skipped " + s);
  }
  for (std::string w : warnings) {
    const std::size_t at = w.find("imu0/data.csv");
    if (at != std::string::npos) w.replace(at, 13, dir + "/imu.txt");
    in.warnings.push_back(w);
  }
  for (const io::EurocFrame& f : covered) {
    in.frames.push_back(std::move(frames[f.line]));
    if (seq.ground_truth) {
      if (!in.gt_T_w_b) in.gt_T_w_b.emplace();
      in.gt_T_w_b->push_back(seq.ground_truth->T_w_b[f.line]);
    }
  }
  return in;
}

namespace {

const char* kFrontendStages[vision::kNumFrontendStages] = {"points", "detection", "lines"};

}  // namespace

VioInput ReadVioEuroc(const std::string& dir, const vision::ImageFrontendOptions& options,
                      bool quiet) {
  const io::EurocDataset data = io::ReadEurocDataset(dir);
  VioInput in;
  in.source = dir;
  in.T_b_c = data.cam0.T_b_c;
  in.imu_model = data.imu.imu_model;
  in.imu = data.imu.imu;
  for (const std::string& s : data.skipped) in.warnings.push_back("skipped " + s);
  in.warnings.insert(in.warnings.end(), data.warnings.begin(), data.warnings.end());
  const vision::Undistorter undistorter(data.cam0.camera);
  in.K = undistorter.ideal_camera().K;
  vision::ImageFrontend frontend(in.K, options);
  std::array<double, vision::kNumFrontendStages> total{};
  const double t_start = ThreadCpuMs();
  for (std::size_t i = 0; i < data.frames.size(); ++i) {
    const io::EurocFrame& frame = data.frames[i];
    window::FrameInput input;
    input.time = frame.t;
    nlohmann::json info = {{"image", frame.image}};
    cv::Mat image;
    try {
      image = undistorter.Undistort(io::ReadGrayImage(frame.image));
    } catch (const std::exception& e) {  // unreadable, or of another size than the calibration
      in.warnings.push_back(std::string("skipped ") + frame.image + ": " + e.what());
      continue;
    }
    BasicStageClock<vision::FrontendStage, vision::kNumFrontendStages> ms;
    const vision::ImageFrontendFrame f = frontend.Process(image, ms.Observer());
    for (int k = 0; k < vision::kNumFrontendStages; ++k) {
      info["ms"][kFrontendStages[k]] = ms.ms(k);
      total[k] += ms.ms(k);
    }
    input.points = f.points;
    input.segments = f.segments;
    info["observed_points"] = f.points.size();
    info["observed_segments"] = f.segments.size();
    in.frames.push_back(std::move(input));
    in.info.push_back(std::move(info));
    if (!quiet) std::cerr << "\rplucker vio: front end " << (i + 1) << "/" << data.frames.size();
  }
  if (!quiet) std::cerr << "\n";
  in.frontend_cpu_ms = ThreadCpuMs() - t_start;
  for (int k = 0; k < vision::kNumFrontendStages; ++k) {
    in.frontend_ms[kFrontendStages[k]] =
        in.frames.empty() ? 0.0 : total[k] / static_cast<double>(in.frames.size());
  }
  if (!data.imu.ground_truth.empty()) {
    // The ground-truth state nearest each frame (20 Hz, as the camera).
    std::vector<SE3d> gt;
    std::size_t k = 0;
    for (const auto& f : in.frames) {
      while (k + 1 < data.imu.ground_truth.size() &&
             std::abs(data.imu.ground_truth[k + 1].t - f.time) <=
                 std::abs(data.imu.ground_truth[k].t - f.time)) {
        ++k;
      }
      gt.push_back(data.imu.ground_truth[k].T_w_b);
    }
    in.gt_T_w_b = gt;
  }
  return in;
}

}  // namespace app
}  // namespace plucker
