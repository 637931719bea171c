// `plucker convert strecha --cameras DIR --out poses.txt`: the ground truth of a Strecha
// multi-view set (one `<image>.camera` file per image, io/camera_calibration.h) as a KITTI poses
// file, one `T_w_c` line per camera file in name order (= the image order of the images
// folder), so that `plucker eval ate --align sim3` compares a reconstruction with it.
// `plucker convert euroc-gt (--euroc DIR | --csv FILE) --out gt.tum`: a EuRoC ground truth
// (state_groundtruth_estimate0/data.csv) as a TUM trajectory of the body (IMU) frame T_w_b, its
// stamps the dataset's own nanoseconds written as exact decimal seconds, so that evo or
// `plucker eval ate` compare it with an estimate on the same clock as they are.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"
#include "plucker/io/camera_calibration.h"
#include "plucker/io/euroc_dataset.h"
#include "plucker/io/euroc_imu.h"
#include "plucker/io/trajectory_io.h"
#include "run_guarded.h"

namespace plucker {
namespace app {
namespace {

struct StrechaArgs {
  std::string cameras, out;
  bool quiet = false;
};

void RunStrecha(const StrechaArgs& a) {
  if (a.out.size() >= 7 && a.out.compare(a.out.size() - 7, 7, ".camera") == 0) {
    throw std::invalid_argument("--out " + a.out + " looks like an input .camera file; refusing");
  }
  std::vector<SE3d> poses;
  const std::vector<std::string> files = io::ListStrechaCameraFiles(a.cameras);
  for (const std::string& file : files) poses.push_back(io::ReadStrechaCamera(file).T_w_c);
  io::WriteKittiPoses(a.out, poses);
  if (!a.quiet) {
    std::cout << "wrote " << poses.size() << " poses T_w_c (camera to world, translation = "
              << "camera centre) from " << a.cameras << " to " << a.out << "\n";
  }
}

struct EurocGtArgs {
  std::string euroc, csv, out, camera_poses;
  bool quiet = false;
};

// The cam0 pose T_w_c = T_w_b T_b_c at every usable image of the folder, from the ground-truth
// state nearest its time (within 10 ms, else an error naming the image's row), as KITTI poses:
// the ground truth of `plucker vo` on the images (one line per image of data.csv that the IMU
// covers, in order; `plucker eval ate --align sim3`).
void WriteEurocCameraPoses(const EurocGtArgs& a, const io::EurocGroundTruth& gt) {
  const io::EurocDataset data = io::ReadEurocDataset(a.euroc);
  std::vector<SE3d> T_w_c;
  for (const io::EurocFrame& f : data.frames) {
    auto after = std::lower_bound(gt.states.begin(), gt.states.end(), f.t,
                                  [](const sensor::BodyState& s, double t) { return s.t < t; });
    if (after == gt.states.end() ||
        (after != gt.states.begin() && f.t - (after - 1)->t < after->t - f.t)) {
      --after;
    }
    if (std::abs(after->t - f.t) > 0.01) {
      throw io::IoError(a.euroc + "/mav0/cam0/data.csv:" + std::to_string(f.line),
                        "no ground-truth state within 10 ms of this image");
    }
    T_w_c.push_back(after->T_w_b * data.cam0.T_b_c);
  }
  io::WriteKittiPoses(a.camera_poses, T_w_c);
  if (!a.quiet) {
    std::cout << "wrote " << T_w_c.size() << " cam0 poses T_w_c to " << a.camera_poses << "\n";
  }
}

void RunEurocGt(const EurocGtArgs& a) {
  if (a.euroc.empty() == a.csv.empty()) throw std::invalid_argument("give --euroc or --csv");
  if (!a.camera_poses.empty() && a.euroc.empty()) {
    throw std::invalid_argument("--camera-poses needs --euroc (the images and cam0/sensor.yaml)");
  }
  const std::string source =
      a.csv.empty() ? a.euroc + "/mav0/state_groundtruth_estimate0/data.csv" : a.csv;
  if (a.out.size() >= 4 && a.out.compare(a.out.size() - 4, 4, ".csv") == 0) {
    throw std::invalid_argument("--out " + a.out + " looks like an input .csv file; refusing");
  }
  io::EurocGroundTruth gt;
  if (a.csv.empty()) {
    io::EurocImuRecording r = io::ReadEurocImuRecording(a.euroc);
    if (r.ground_truth.empty()) throw io::IoError(source, "no ground truth in this folder");
    gt.origin_ns = r.origin_ns;
    gt.states = std::move(r.ground_truth);
  } else {
    gt = io::ReadEurocGroundTruthCsv(a.csv);
  }
  std::vector<double> times;
  std::vector<SE3d> poses;
  for (const sensor::BodyState& s : gt.states) {
    times.push_back(s.t);
    poses.push_back(s.T_w_b);
  }
  io::WriteTumTrajectoryOnClock(
      a.out, gt.origin_ns, times, poses,
      {"EuRoC ground truth " + source, "T_w_b: body (IMU) frame in the ground truth's world"});
  if (!a.quiet) {
    std::cout << "wrote " << poses.size() << " poses T_w_b from " << source << " to " << a.out
              << "\n";
  }
  if (!a.camera_poses.empty()) WriteEurocCameraPoses(a, gt);
}

}  // namespace

void RegisterConvert(CLI::App& app, int* exit_code) {
  CLI::App* cmd = app.add_subcommand("convert", "Convert dataset ground truth to plucker formats");
  cmd->require_subcommand(1);
  auto args = std::make_shared<StrechaArgs>();
  CLI::App* strecha = cmd->add_subcommand(
      "strecha", "Strecha <image>.camera files -> KITTI poses (T_w_c, one line per file)");
  strecha->add_option("--cameras", args->cameras, "Folder of the *.camera files")->required();
  strecha->add_option("--out", args->out, "KITTI poses file to write")->required();
  strecha->add_flag("--quiet", args->quiet, "No summary line");
  strecha->callback(
      [args, exit_code] { RunGuarded("convert", exit_code, [&] { RunStrecha(*args); }); });
  auto gt_args = std::make_shared<EurocGtArgs>();
  CLI::App* euroc = cmd->add_subcommand(
      "euroc-gt", "EuRoC ground truth csv -> TUM T_w_b on the dataset's clock (seconds)");
  euroc->add_option("--euroc", gt_args->euroc, "EuRoC folder (with mav0/)");
  euroc->add_option("--csv", gt_args->csv, "A ground-truth csv (state_groundtruth_estimate0)");
  euroc->add_option("--out", gt_args->out, "TUM file to write")->required();
  euroc->add_option("--camera-poses", gt_args->camera_poses,
                    "Also write the cam0 poses T_w_c at the images' times as KITTI poses");
  euroc->add_flag("--quiet", gt_args->quiet, "No summary line");
  euroc->callback(
      [gt_args, exit_code] { RunGuarded("convert", exit_code, [&] { RunEurocGt(*gt_args); }); });
}

}  // namespace app
}  // namespace plucker
