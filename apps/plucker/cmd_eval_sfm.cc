// plucker eval sfm --gt DIR --est poses.txt [--align sim3|se3] [--json]: camera centre and
// rotation errors of a reconstruction (`plucker sfm` poses.txt, twelve `nan` for an unregistered
// view) against Strecha ground-truth cameras (a folder of `*.camera` files in name order, or a
// dataset folder with such a `cameras/` sub-folder), after alignment (eval/camera_set.h).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "plucker/eval/camera_set.h"
#include "plucker/io/camera_calibration.h"
#include "plucker/io/io_error.h"
#include "plucker/io/trajectory_io.h"
#include "run_guarded.h"

namespace plucker {
namespace app {
namespace {

namespace fs = std::filesystem;

struct EvalSfmArgs {
  std::string gt, est, align = "sim3";
  bool json = false;
};

int Run(const EvalSfmArgs& a) {
  const std::string dir =
      fs::is_directory(fs::path(a.gt) / "cameras") ? (fs::path(a.gt) / "cameras").string() : a.gt;
  std::vector<SE3d> gt;
  for (const std::string& file : io::ListStrechaCameraFiles(dir))
    gt.push_back(io::ReadStrechaCamera(file).T_w_c);
  const std::vector<std::optional<SE3d>> est = io::ReadKittiPosesWithGaps(a.est);
  const eval::AlignmentMode mode =
      a.align == "se3" ? eval::AlignmentMode::kSE3 : eval::AlignmentMode::kSim3;
  const eval::CameraSetErrors e = eval::CompareCameraSets(est, gt, mode);
  if (!e.ok) throw io::IoError(a.est, e.message);
  if (a.json) {
    const nlohmann::json j = {{"cameras", e.cameras},
                              {"registered", e.registered},
                              {"missing", e.missing},
                              {"align", a.align},
                              {"scale", e.scale},
                              {"median_centre_mm", 1e3 * e.median_centre},
                              {"max_centre_mm", 1e3 * e.max_centre},
                              {"median_rotation_deg", e.median_rotation_deg},
                              {"max_rotation_deg", e.max_rotation_deg},
                              {"median_rotation_centres_deg", e.median_rotation_centres_deg},
                              {"max_rotation_centres_deg", e.max_rotation_centres_deg},
                              {"centre_error_mm", e.centre_error},
                              {"rotation_error_deg", e.rotation_error_deg}};
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::printf("cameras %d, registered %d (alignment %s, scale %.6g)\n", e.cameras, e.registered,
              a.align.c_str(), e.scale);
  std::printf("centre error   median %.2f mm, max %.2f mm\n", 1e3 * e.median_centre,
              1e3 * e.max_centre);
  std::printf(
      "rotation error median %.4f deg, max %.4f deg (rotation fitted to the orientations)\n",
      e.median_rotation_deg, e.max_rotation_deg);
  std::printf("rotation error median %.4f deg, max %.4f deg (rotation of the centres' alignment)\n",
              e.median_rotation_centres_deg, e.max_rotation_centres_deg);
  return 0;
}

}  // namespace

void RegisterEvalSfm(CLI::App& eval_cmd, int* exit_code) {
  auto a = std::make_shared<EvalSfmArgs>();
  CLI::App* cmd = eval_cmd.add_subcommand(
      "sfm", "Camera centre and rotation errors of `plucker sfm` poses against Strecha cameras");
  cmd->add_option("--gt", a->gt, "Folder of Strecha *.camera files (or its parent)")->required();
  cmd->add_option("--est", a->est, "poses.txt of `plucker sfm` (KITTI; nan rows: unregistered)")
      ->required();
  cmd->add_option("--align", a->align, "sim3 or se3")
      ->check(CLI::IsMember({"sim3", "se3"}))
      ->capture_default_str();
  cmd->add_flag("--json", a->json, "Print JSON");
  cmd->callback([a, exit_code]() { RunGuarded("eval sfm", exit_code, [&] { return Run(*a); }); });
}

}  // namespace app
}  // namespace plucker
