// plucker bench lidar: the LiDAR odometry's time per frame, including reading the scan from disk,
// with one thread and with several, interleaved in one run so that both see the same machine
// load. Each frame keeps its fastest repeat; the table gives the median over frames, per stage.
#include <algorithm>
#include <array>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "commands.h"
#include "lidar_sequence_defaults.h"
#include "plucker/eval/statistics.h"
#include "plucker/io/lidar_sequence.h"
#include "plucker/lidar/odometry.h"
#include "stage_clock.h"

namespace plucker {
namespace app {
namespace {

struct BenchLidarArgs {
  std::string data, sequence;
  std::vector<int> threads = {1, 2};
  int repeats = 3;
  int frames = 0;  // 0: all
  bool json = false;
};

constexpr int kStages = 7;  // read, rings, features, correspondences, solve, map update, total
const char* const kStageNames[kStages] = {"read",  "rings",      "features", "correspondences",
                                          "solve", "map_update", "total"};

// Per frame: the stage times of one pass over the sequence (CPU time of the thread with one
// thread, wall-clock with several: see StageClock).
std::vector<std::array<double, kStages>> RunOnce(const io::LidarSequence& seq, int frames,
                                                 int threads) {
  lidar::LidarOdometryOptions options;
  options.num_threads = threads;
  AdaptToSequence(seq, &options);
  lidar::LidarOdometry odometry(options);
  const bool wall = threads > 1;
  StageClock stages(wall);
  auto now = [wall] { return wall ? WallMs() : ThreadCpuMs(); };
  std::vector<std::array<double, kStages>> out;
  for (int i = 0; i < frames; ++i) {
    const double t0 = now();
    LidarScan scan;
    std::string error;
    if (!seq.Read(i, &scan, &error)) {
      odometry.SkipFrame(error);
      continue;
    }
    const double read = now() - t0;
    odometry.ProcessScan(std::move(scan), stages.Observer());
    out.push_back({read, stages.ms(lidar::Stage::kRings), stages.ms(lidar::Stage::kFeatures),
                   stages.ms(lidar::Stage::kCorrespondences), stages.ms(lidar::Stage::kSolve),
                   stages.ms(lidar::Stage::kMapUpdate), now() - t0});
  }
  return out;
}

int RunBenchLidar(const BenchLidarArgs& args) {
  const io::LidarSequence seq = io::LidarSequence::Open(args.data, args.sequence);
  const int frames = args.frames > 0 ? std::min<int>(args.frames, static_cast<int>(seq.size()))
                                     : static_cast<int>(seq.size());
  // best[t][frame][stage]: the fastest repeat of each frame.
  std::vector<std::vector<std::array<double, kStages>>> best(args.threads.size());
  for (int rep = 0; rep < args.repeats; ++rep) {
    for (std::size_t t = 0; t < args.threads.size(); ++t) {
      const auto run = RunOnce(seq, frames, args.threads[t]);
      if (best[t].empty()) {
        best[t] = run;
        continue;
      }
      for (std::size_t f = 0; f < run.size() && f < best[t].size(); ++f)
        if (run[f][kStages - 1] < best[t][f][kStages - 1]) best[t][f] = run[f];
    }
  }
  nlohmann::json j = {{"data", seq.description()}, {"frames", frames}, {"repeats", args.repeats}};
  if (!args.json) {
    std::printf("%s: %d frames, fastest of %d repeats per frame; median ms per frame\n",
                seq.description().c_str(), frames, args.repeats);
    std::printf("%-8s", "threads");
    for (const char* name : kStageNames) std::printf(" %15s", name);
    std::printf(" %10s %8s\n", "p95 total", "fps");
  }
  std::vector<double> medians;
  for (std::size_t t = 0; t < args.threads.size(); ++t) {
    nlohmann::json row = {{"threads", args.threads[t]},
                          {"clock", args.threads[t] == 1 ? "thread CPU" : "wall"}};
    if (!args.json) std::printf("%-8d", args.threads[t]);
    std::vector<double> total;
    for (int s = 0; s < kStages; ++s) {
      std::vector<double> v;
      for (const auto& f : best[t]) v.push_back(f[s]);
      const double median = eval::Percentile(v, 0.5);
      row["median_ms"][kStageNames[s]] = median;
      if (!args.json) std::printf(" %15.2f", median);
      if (s == kStages - 1) total = v;
    }
    const double p95 = eval::Percentile(total, 0.95), median = eval::Percentile(total, 0.5);
    medians.push_back(median);
    row["p95_total_ms"] = p95;
    row["fps"] = 1000.0 / std::max(median, 1e-9);
    if (!args.json) std::printf(" %10.2f %8.1f\n", p95, 1000.0 / std::max(median, 1e-9));
    j["runs"].push_back(row);
  }
  if (args.json) {
    std::cout << j.dump(2) << "\n";
  } else {
    std::printf("one thread: thread CPU time (robust to a loaded machine); several: wall-clock\n");
    for (std::size_t t = 1; t < medians.size(); ++t)
      std::printf("speed-up %d vs %d threads: %.2fx\n", args.threads[t], args.threads[0],
                  medians[0] / std::max(medians[t], 1e-9));
  }
  return 0;
}

}  // namespace

void RegisterBenchLidar(CLI::App& bench, int* exit_code) {
  auto args = std::make_shared<BenchLidarArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "lidar", "LiDAR odometry time per frame (with reading), one thread vs several");
  cmd->add_option("--data", args->data, "Sequence folder or dataset root (as plucker lidar)")
      ->required();
  cmd->add_option("--sequence", args->sequence, "Sequence name under DATA/sequences");
  cmd->add_option("--threads", args->threads, "Thread counts to compare")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd->add_option("--repeats", args->repeats, "Passes per thread count (fastest kept per frame)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  cmd->add_option("--frames", args->frames, "Use the first N frames (0: all)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000000));
  cmd->add_flag("--json", args->json, "Machine-readable output");
  cmd->callback([args, exit_code]() { *exit_code = RunBenchLidar(*args); });
}

}  // namespace app
}  // namespace plucker
