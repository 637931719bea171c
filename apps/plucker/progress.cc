#include "progress.h"

#include <unistd.h>

#include <cstdio>
#include <iostream>

#include "stage_clock.h"

namespace plucker {
namespace app {

FrameProgress::FrameProgress(std::string name, std::size_t n, bool quiet, std::size_t every)
    : name_(std::move(name)),
      n_(n),
      every_(every),
      quiet_(quiet),
      terminal_(isatty(fileno(stderr)) == 1) {}

bool FrameProgress::Due(std::size_t i) {
  if (quiet_) return false;
  if (!terminal_) return every_ > 0 && ((i + 1) % every_ == 0 || i + 1 == n_);
  const double now = WallMs();
  if (now - last_ms_ <= 500.0 && i + 1 != n_) return false;
  last_ms_ = now;
  return true;
}

void FrameProgress::Show(std::size_t i, const std::string& detail) {
  const std::string line = name_ + ": frame " + std::to_string(i + 1) + "/" + std::to_string(n_);
  if (terminal_) {
    std::cerr << "\r" << line << "  " << detail << "   " << std::flush;
    open_ = true;
  } else {
    std::cerr << line << "  " << detail << "\n";
  }
}

void FrameProgress::Break() {
  if (open_) std::cerr << "\n";
  open_ = false;
}

}  // namespace app
}  // namespace plucker
