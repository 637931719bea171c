// Progress of a frame loop on stderr: on a terminal one line rewritten in place (carriage
// return, at most every 0.5 s); else (a log file, a pipe) one plain line every `every` frames
// and the last one (0: none), so logs do not fill with carriage-return updates. Quiet: nothing.
// Warnings are not progress: the caller prints them whatever this does.
#pragma once

#include <cstddef>
#include <string>

namespace plucker {
namespace app {

class FrameProgress {
 public:
  // name: the command ("plucker vio"); n: the frames to come.
  FrameProgress(std::string name, std::size_t n, bool quiet, std::size_t every = 100);
  // Whether frame i (0-based) should be shown now; then Show the line's tail.
  bool Due(std::size_t i);
  void Show(std::size_t i, const std::string& detail);
  // Before a warning mid-run (ends the in-place line) and at the end of the loop.
  void Break();

 private:
  std::string name_;
  std::size_t n_, every_;
  bool quiet_, terminal_, open_ = false;
  double last_ms_ = -1e300;
};

}  // namespace app
}  // namespace plucker
