// plucker eval sfm --gt DIR --est poses.txt [--align sim3|se3] [--json]: camera centre and
// rotation errors of a reconstruction (`plucker sfm` poses.txt, twelve `nan` for an unregistered
// view) against Strecha ground-truth cameras (a folder of `*.camera` files in name order, or a
// dataset folder with such a `cameras/` sub-folder), after alignment (eval/camera_set.h).
// --ref poses.txt instead of --gt: against a reference reconstruction (KITTI T_w_c rows, e.g. one
// made with every point, or COLMAP's), for the precision a run loses against it; a reference
// camera that is nan is left out of the comparison.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

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
  std::string gt, ref, est, align = "sim3";
  bool json = false;
};

// The cameras to compare against: Strecha .camera files (--gt) or a reference poses.txt (--ref).
// A reference camera that is nan drops that camera from the estimate as well.
std::vector<SE3d> ReadReference(const EvalSfmArgs& a, std::vector<std::optional<SE3d>>* est) {
  std::vector<SE3d> gt;
  if (a.ref.empty()) {
    const std::string dir =
        fs::is_directory(fs::path(a.gt) / "cameras") ? (fs::path(a.gt) / "cameras").string() : a.gt;
    for (const std::string& file : io::ListStrechaCameraFiles(dir))
      gt.push_back(io::ReadStrechaCamera(file).T_w_c);
    return gt;
  }
  const std::vector<std::optional<SE3d>> ref = io::ReadKittiPosesWithGaps(a.ref);
  if (ref.size() != est->size()) {
    throw io::IoError(a.est, "the estimate has " + std::to_string(est->size()) +
                                 " cameras, the reference " + a.ref + " " +
                                 std::to_string(ref.size()));
  }
  std::vector<std::optional<SE3d>> kept;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    if (!ref[i]) continue;
    gt.push_back(*ref[i]);
    kept.push_back((*est)[i]);
  }
  *est = kept;
  return gt;
}

int Run(const EvalSfmArgs& a) {
  if (a.gt.empty() == a.ref.empty()) throw std::invalid_argument("give exactly one of --gt, --ref");
  std::vector<std::optional<SE3d>> est = io::ReadKittiPosesWithGaps(a.est);
  const std::vector<SE3d> gt = ReadReference(a, &est);
  const eval::AlignmentMode mode =
      a.align == "se3" ? eval::AlignmentMode::kSE3 : eval::AlignmentMode::kSim3;
  const eval::CameraSetErrors e = eval::CompareCameraSets(est, gt, mode);
  if (!e.ok) throw io::IoError(a.est, e.message);
  if (a.json) {
    const nlohmann::json j = {{"cameras", e.cameras},
                              {"registered", e.registered},
                              {"missing", e.missing},
                              {"align", a.align},
                              {"reference", a.ref.empty() ? "gt" : a.ref},
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
  std::printf("cameras %d, registered %d (alignment %s, scale %.6g%s)\n", e.cameras, e.registered,
              a.align.c_str(), e.scale, a.ref.empty() ? "" : ", against the reference");
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
  cmd->add_option("--gt", a->gt, "Folder of Strecha *.camera files (or its parent)");
  cmd->add_option("--ref", a->ref,
                  "Instead of --gt: a reference poses.txt (KITTI T_w_c rows, nan: left out), "
                  "e.g. a reconstruction with every point");
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
