#include "bench_lidar_long.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "plucker/eval/statistics.h"
#include "plucker/io/io_error.h"
#include "plucker/io/kitti_lidar.h"
#include "plucker/sensor/lidar_model.h"
#include "plucker/sim/lidar_scene.h"
#include "plucker/sim/lidar_sim.h"
#include "stage_clock.h"

namespace plucker {
namespace app {

// read, the odometry's stages (stage_clock.h), total.
const std::array<const char*, kLidarStages> kBenchStageNames = [] {
  std::array<const char*, kLidarStages> names{};
  names.front() = kLidarReadStageName;
  for (int s = 0; s < lidar::kNumStages; ++s) names[1 + s] = kLidarStageNames[s];
  names.back() = "total";
  return names;
}();

std::vector<BlockMedians> MediansPerBlock(const std::vector<StageTimes>& frames,
                                          std::size_t block_size) {
  std::vector<BlockMedians> blocks;
  block_size = std::max<std::size_t>(1, block_size);
  std::vector<double> values;
  for (std::size_t first = 0; first < frames.size(); first += block_size) {
    BlockMedians block;
    block.first = first;
    block.last = std::min(frames.size(), first + block_size) - 1;
    for (int s = 0; s < kLidarStages; ++s) {
      values.clear();
      for (std::size_t f = block.first; f <= block.last; ++f) values.push_back(frames[f][s]);
      block.median[s] = eval::Percentile(values, 0.5);
    }
    blocks.push_back(block);
  }
  return blocks;
}

void PrintBlockTable(const std::vector<BlockMedians>& blocks) {
  std::printf("%-11s", "frames");
  for (const char* name : kBenchStageNames) std::printf(" %15s", name);
  std::printf("\n");
  for (const BlockMedians& b : blocks) {
    char range[32];
    std::snprintf(range, sizeof(range), "%zu-%zu", b.first, b.last);
    std::printf("%-11s", range);
    for (double v : b.median) std::printf(" %15.2f", v);
    std::printf("\n");
  }
  if (blocks.size() >= 2) {
    const double first = blocks.front().median[kLidarStages - 1];
    const double last = blocks.back().median[kLidarStages - 1];
    std::printf("growth of the median total, last block / first block: %.2fx\n",
                last / std::max(first, 1e-9));
  }
}

struct SimulatedDrive::State {
  State(const std::string& scene_name, const sensor::LidarModel& sensor_model, std::uint64_t seed)
      : sensor(sensor_model),
        scene(sim::MakeScene(scene_name, seed)),
        trajectory(scene.route),
        simulator(scene, sim::LidarSimOptionsFor(sensor, 0.02, false, seed)),
        scene_name(scene_name) {}
  sensor::LidarModel sensor;
  sim::LidarScene scene;
  sim::VehicleTrajectory trajectory;
  sim::LidarSimulator simulator;
  std::string scene_name;
  std::string bytes;  // the last simulated frame as a KITTI .bin
  std::size_t frame = 0;
};

SimulatedDrive::SimulatedDrive(const std::string& scene, const std::string& sensor,
                               std::uint64_t seed)
    : state_(std::make_unique<State>(scene, sensor::LidarModelFromName(sensor), seed)) {}
SimulatedDrive::~SimulatedDrive() = default;

void SimulatedDrive::Simulate(std::size_t frame) {
  const double t = static_cast<double>(frame) / state_->sensor.rate_hz;
  state_->bytes = io::SerializeKittiBin(state_->simulator.Scan(state_->trajectory, t, frame));
  state_->frame = frame;
}

bool SimulatedDrive::Read(std::size_t frame, LidarScan* scan, std::string* error) const {
  if (frame != state_->frame) throw std::logic_error("SimulatedDrive: Read before Simulate");
  try {
    io::ParseKittiBin(state_->bytes, "simulated frame " + std::to_string(frame), scan);
  } catch (const io::IoError& e) {
    *error = e.what();
    return false;
  }
  return true;
}

std::string SimulatedDrive::description() const {
  return "simulated " + state_->scene_name + " drive, " + state_->sensor.name +
         " (generated in memory; read = parsing the .bin bytes)";
}

}  // namespace app
}  // namespace plucker
