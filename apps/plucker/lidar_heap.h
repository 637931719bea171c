// Heap settings for the LiDAR commands (`plucker lidar`, `plucker bench lidar`): both must run the
// odometry on the same heap, or the bench times page faults that the program does not have.
#pragma once

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>

namespace plucker {
namespace app {

// The buffers of a scan stream (the file, the scan, its rings and features, the maps: ~10 MB at
// 120k points) come from the heap, grown in one step and backed by transparent huge pages where
// the kernel gives them on request (madvise mode): their first touch then costs a fault per 2 MB
// instead of per 4 KB. Harmless where THP is off (plain pages).
inline void HeapOnHugePages() {
  constexpr std::size_t kHuge = 2 << 20, kPad = 256 << 20;
  mallopt(M_MMAP_THRESHOLD, 64 << 20);   // scan buffers from the heap, not from fresh mmaps
  mallopt(M_TRIM_THRESHOLD, 512 << 20);  // and the heap is not given back between scans
  mallopt(M_TOP_PAD, kPad);              // the next growth reserves kPad at once
  void* probe = malloc(kHuge);           // larger than the heap's free top: grows it
  const auto from = (reinterpret_cast<std::uintptr_t>(probe) + kHuge - 1) & ~(kHuge - 1);
  const auto to = reinterpret_cast<std::uintptr_t>(sbrk(0)) & ~(kHuge - 1);
  if (probe != nullptr && to > from)
    madvise(reinterpret_cast<void*>(from), to - from, MADV_HUGEPAGE);  // a hint: errors ignored
  free(probe);
}

}  // namespace app
}  // namespace plucker
