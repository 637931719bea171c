// The LiDAR part of `plucker demo`.
#pragma once

#include <cstdint>
#include <filesystem>

namespace plucker {
namespace app {

// Simulates a drive, runs the odometry, evaluates it, writes poses, stats and a plot under `dir`.
// Returns the process exit code.
int RunLidarDemo(const std::filesystem::path& dir, int frames, std::uint64_t seed);

}  // namespace app
}  // namespace plucker
