// `plucker convert strecha --cameras DIR --out poses.txt`: the ground truth of a Strecha
// multi-view set (one `<image>.camera` file per image, io/camera_calibration.h) as a KITTI poses
// file, one `T_w_c` line per camera file in name order (= the image order of the images
// folder), so that `plucker eval ate --align sim3` compares a reconstruction with it.
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"
#include "plucker/io/camera_calibration.h"
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
}

}  // namespace app
}  // namespace plucker
