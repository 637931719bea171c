// Errors of the io layer: every message names the file and the problem.
#pragma once

#include <stdexcept>
#include <string>

namespace plucker {
namespace io {

class IoError : public std::runtime_error {
 public:
  IoError(const std::string& path, const std::string& problem)
      : std::runtime_error(path + ": " + problem), path_(path), problem_(problem) {}
  const std::string& path() const { return path_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string path_;
  std::string problem_;
};

// Writes `content` to `path` through a temporary file in the same folder and a rename, so a
// failed write never leaves a truncated file behind. Throws IoError.
void WriteFileAtomically(const std::string& path, const std::string& content);

}  // namespace io
}  // namespace plucker
