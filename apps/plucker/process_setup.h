// Process-wide settings of the pipeline commands, in one place: OpenCV's thread pool and glibc's
// heap. Each pipeline's preset says why it differs from the others; `plucker bench lidar` must use
// the same preset as `plucker lidar`, or the bench times page faults that the program does not
// have. OpenCV-free (the LiDAR commands do not load OpenCV): the caller that links OpenCV passes
// cv::setNumThreads.
#pragma once

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>

namespace plucker {
namespace app {

struct ProcessSetup {
  // cv::setNumThreads(opencv_threads) where >= 0 (0: OpenCV's own pool off, everything on the
  // calling thread); -1 leaves OpenCV as it is.
  int opencv_threads = -1;
  // glibc mallopt values in bytes; 0 leaves glibc's default.
  int mmap_threshold = 0;  // allocations at least this large come from fresh mmaps
  int trim_threshold = 0;  // free heap top kept before it is given back
  int top_pad = 0;         // extra reserved at each heap growth
  // Grow the heap once (by top_pad) and ask for transparent huge pages over it (madvise mode).
  bool heap_on_huge_pages = false;
};

// `plucker vo` and `plucker vio` (the image front end on one thread): OpenCV's pool off (KLT,
// corners, RANSAC run on the calling thread; Ceres runs with num_threads = 1); the front end
// allocates MB-sized temporaries per image (corner responses, pyramids): served by fresh mmaps,
// each page faults again every frame (measured on `plucker vo --no-lines` on KITTI: 40 ms of 48
// in the points stage), so they stay on the heap.
inline ProcessSetup ImagePipelineSetup() {
  ProcessSetup s;
  s.opencv_threads = 0;
  s.mmap_threshold = 64 << 20;
  s.trim_threshold = 128 << 20;
  return s;
}

// `plucker lidar` and `plucker bench lidar`: the buffers of a scan stream (the file, the scan,
// its rings and features, the maps: ~10 MB at 120k points) come from the heap, grown in one step
// of 256 MB and backed by transparent huge pages where the kernel gives them on request: their
// first touch then costs a fault per 2 MB instead of per 4 KB (harmless where THP is off). The
// heap is not given back between scans (trim 512 MB). No OpenCV.
inline ProcessSetup LidarPipelineSetup() {
  ProcessSetup s;
  s.mmap_threshold = 64 << 20;
  s.trim_threshold = 512 << 20;
  s.top_pad = 256 << 20;
  s.heap_on_huge_pages = true;
  return s;
}

inline void GrowHeapOnHugePages() {
  constexpr std::size_t kHuge = 2 << 20;
  void* probe = malloc(kHuge);  // larger than the heap's free top: grows it (by top_pad)
  const auto from = (reinterpret_cast<std::uintptr_t>(probe) + kHuge - 1) & ~(kHuge - 1);
  const auto to = reinterpret_cast<std::uintptr_t>(sbrk(0)) & ~(kHuge - 1);
  if (probe != nullptr && to > from)
    madvise(reinterpret_cast<void*>(from), to - from, MADV_HUGEPAGE);  // a hint: errors ignored
  free(probe);
}

// Applies s; set_opencv_threads (cv::setNumThreads) is required when s.opencv_threads >= 0.
inline void SetUpProcess(const ProcessSetup& s, void (*set_opencv_threads)(int) = nullptr) {
  if (s.opencv_threads >= 0) {
    if (set_opencv_threads == nullptr)
      throw std::logic_error("SetUpProcess: OpenCV threads set without cv::setNumThreads");
    set_opencv_threads(s.opencv_threads);
  }
  if (s.mmap_threshold > 0) mallopt(M_MMAP_THRESHOLD, s.mmap_threshold);
  if (s.trim_threshold > 0) mallopt(M_TRIM_THRESHOLD, s.trim_threshold);
  if (s.top_pad > 0) mallopt(M_TOP_PAD, s.top_pad);
  if (s.heap_on_huge_pages) GrowHeapOnHugePages();
}

}  // namespace app
}  // namespace plucker
