// Pieces of `plucker bench lidar --long`: per-frame stage times, their medians per block of
// frames (so that growth of the time per frame along a long sequence is visible), and a
// simulated drive generated frame by frame in memory (no folder needed).
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "plucker/sensor/lidar_scan.h"

namespace plucker {
namespace app {

// Milliseconds per stage of one frame: read, rings, features, correspondences, solve, map update
// and the frame's total (read + odometry).
constexpr int kLidarStages = 7;
extern const std::array<const char*, kLidarStages> kBenchStageNames;  // read, stages, total
using StageTimes = std::array<double, kLidarStages>;

struct BlockMedians {
  std::size_t first = 0, last = 0;  // frame range (inclusive) of the block
  StageTimes median{};              // per stage, the median over the block's frames
};

// Splits the frames into consecutive blocks of `block_size` (the last may be shorter) and takes
// the per-stage median of each.
std::vector<BlockMedians> MediansPerBlock(const std::vector<StageTimes>& frames,
                                          std::size_t block_size);

// Prints the block table (one row per block, one column per stage) and, last, the ratio of the
// last block's total to the first full block's (1.00 = no growth).
void PrintBlockTable(const std::vector<BlockMedians>& blocks);

// A simulated street drive (the `plucker sim lidar` scene and sensor), one scan per Next() call,
// serialised to KITTI .bin bytes in memory: the benchmark times the parse of those bytes as
// the read stage, so the sequence needs no disk space.
class SimulatedDrive {
 public:
  SimulatedDrive(const std::string& scene, const std::string& sensor, std::uint64_t seed);
  ~SimulatedDrive();
  void Simulate(std::size_t frame);  // not timed: makes the bytes of `frame`
  // Parses the bytes of the last simulated frame into *scan (timed as `read`).
  bool Read(std::size_t frame, LidarScan* scan, std::string* error) const;
  std::string description() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace app
}  // namespace plucker
