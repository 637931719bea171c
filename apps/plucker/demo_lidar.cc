#include "demo_lidar.h"

#include <cstdio>

namespace plucker {
namespace app {

int RunLidarDemo(const std::filesystem::path& dir, int frames, std::uint64_t seed) {
  (void)dir;
  (void)frames;
  (void)seed;
  std::printf("== LiDAR: (not yet wired) ==\n");
  return 0;
}

}  // namespace app
}  // namespace plucker
