// plucker bench lidar: the LiDAR odometry's time per frame, including reading the scan from disk,
// with one thread and with several, interleaved in one run so that both see the same machine
// load. Each frame keeps its fastest repeat; the table gives the median over frames, per stage.
// --long: one pass over a long sequence (a simulated drive made on the fly, or --data) with the
// per-stage medians per block of frames, to show whether the time per frame grows.
#include <algorithm>
#include <array>
#include <cstdio>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench_lidar_long.h"
#include "commands.h"
#include "lidar_sequence_defaults.h"
#include "plucker/eval/statistics.h"
#include "plucker/io/lidar_sequence.h"
#include "plucker/lidar/odometry.h"
#include "process_setup.h"
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
  bool long_mode = false;  // --long
  int block = 100;
  int sim_frames = 1200;
  std::string sensor = "hdl64";
};

constexpr int kStages = kLidarStages;
const std::array<const char*, kStages>& kStageNames = kBenchStageNames;
// Reads frame i into *scan; *stamp receives its time (s) also when the read fails, so that a
// skipped frame is predicted at its time, as `plucker lidar` does.
using ReadFn = std::function<bool(int, LidarScan*, std::string*, double*)>;

// The time of frame i of `seq`: times.txt / the file names when known, else 10 Hz.
double StampOf(const io::LidarSequence& seq, int i) {
  const auto k = static_cast<std::size_t>(i);
  return k < seq.times().size() ? seq.times()[k] : 0.1 * i;
}

// Per frame: the stage times of one pass over the sequence (CPU time of the thread with one
// thread, wall-clock with several: see StageClock). `prepare(i)` (optional) runs before frame i,
// untimed.
std::vector<StageTimes> RunOnce(const ReadFn& read_frame, lidar::LidarOdometryOptions options,
                                int frames, int threads,
                                const std::function<void(int)>& prepare = nullptr) {
  options.num_threads = threads;
  lidar::LidarOdometry odometry(options);
  const bool wall = threads > 1;
  StageClock stages(wall);
  auto now = [wall] { return wall ? WallMs() : ThreadCpuMs(); };
  std::vector<StageTimes> out;
  LidarScan scan;  // refilled in place by every read
  for (int i = 0; i < frames; ++i) {
    if (prepare) prepare(i);
    const double t0 = now();
    std::string error;
    double stamp = 0.0;
    if (!read_frame(i, &scan, &error, &stamp)) {
      odometry.SkipFrame(error, stamp);
      continue;
    }
    const double read = now() - t0;
    // ProcessScan(LidarScan&&) works on the scan in place: its buffers stay for the next read.
    odometry.ProcessScan(std::move(scan), stages.Observer());
    out.push_back({read, stages.ms(lidar::Stage::kRings), stages.ms(lidar::Stage::kFeatures),
                   stages.ms(lidar::Stage::kCorrespondences), stages.ms(lidar::Stage::kSolve),
                   stages.ms(lidar::Stage::kMapUpdate), now() - t0});
  }
  return out;
}

// --long: one pass, one thread count (the first of --threads), medians per block of frames.
int RunLongBench(const BenchLidarArgs& args) {
  std::vector<StageTimes> times;
  std::string description;
  if (args.data.empty()) {
    SimulatedDrive drive("urban", args.sensor, 1);
    description = drive.description();
    times = RunOnce(
        [&](int i, LidarScan* scan, std::string* error, double* stamp) {
          *stamp = 0.1 * i;  // the simulated drive's 10 Hz
          return drive.Read(i, scan, error);
        },
        lidar::LidarOdometryOptions(), args.sim_frames, args.threads.front(),
        [&](int i) { drive.Simulate(i); });
  } else {
    const io::LidarSequence seq = io::LidarSequence::Open(args.data, args.sequence);
    description = seq.description();
    lidar::LidarOdometryOptions options;
    AdaptToSequence(seq, &options);
    const int n = static_cast<int>(seq.size());
    times = RunOnce(
        [&](int i, LidarScan* scan, std::string* error, double* stamp) {
          *stamp = StampOf(seq, i);
          return seq.Read(i, scan, error);
        },
        options, args.frames > 0 ? std::min(args.frames, n) : n, args.threads.front());
  }
  const std::vector<BlockMedians> blocks = MediansPerBlock(times, args.block);
  if (args.json) {
    nlohmann::json j = {
        {"data", description}, {"frames", times.size()}, {"threads", args.threads.front()}};
    for (const BlockMedians& b : blocks) {
      nlohmann::json row = {{"first", b.first}, {"last", b.last}};
      for (int s = 0; s < kStages; ++s) row["median_ms"][kStageNames[s]] = b.median[s];
      j["blocks"].push_back(row);
    }
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::printf("%s\n%zu frames, %d thread(s), one pass; median ms per frame per block of %d\n",
              description.c_str(), times.size(), args.threads.front(), args.block);
  PrintBlockTable(blocks);
  return 0;
}

int RunBenchLidar(const BenchLidarArgs& args) {
  SetUpProcess(LidarPipelineSetup());  // as `plucker lidar`
  if (args.long_mode) return RunLongBench(args);
  if (args.data.empty()) throw std::invalid_argument("--data is required (unless --long)");
  const io::LidarSequence seq = io::LidarSequence::Open(args.data, args.sequence);
  const int frames = args.frames > 0 ? std::min<int>(args.frames, static_cast<int>(seq.size()))
                                     : static_cast<int>(seq.size());
  lidar::LidarOdometryOptions options;
  AdaptToSequence(seq, &options);
  const ReadFn read = [&](int i, LidarScan* scan, std::string* error, double* stamp) {
    *stamp = StampOf(seq, i);
    return seq.Read(i, scan, error);
  };
  // best[t][frame][stage]: the fastest repeat of each frame.
  std::vector<std::vector<StageTimes>> best(args.threads.size());
  for (int rep = 0; rep < args.repeats; ++rep) {
    for (std::size_t t = 0; t < args.threads.size(); ++t) {
      const auto run = RunOnce(read, options, frames, args.threads[t]);
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
  cmd->add_option("--data", args->data,
                  "Sequence folder or dataset root (as plucker lidar); required unless --long");
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
  cmd->add_flag("--long", args->long_mode,
                "Long-sequence mode: one pass with the first of --threads, per-stage medians "
                "per block of frames; without --data over a drive simulated on the fly");
  cmd->add_option("--block", args->block, "Frames per block (--long)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--sim-frames", args->sim_frames, "Frames of the simulated drive (--long)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--sensor", args->sensor, "Sensor of the simulated drive (--long)")
      ->capture_default_str()
      ->check(CLI::IsMember({"hdl64", "vlp32", "vlp16"}));
  cmd->callback([args, exit_code]() { *exit_code = RunBenchLidar(*args); });
}

}  // namespace app
}  // namespace plucker
