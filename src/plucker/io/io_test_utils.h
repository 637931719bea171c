// Scratch folders for the io tests (header-only, test use only, not installed).
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace plucker {
namespace io {
namespace testing {

// A fresh, empty folder in the system's temp directory, named after the running test and the
// process (tests run in parallel), removed with everything in it when the object goes away.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& tag = "") {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = "plucker_";
    if (info != nullptr) name += std::string(info->test_suite_name()) + "_" + info->name() + "_";
    path_ = std::filesystem::temp_directory_path() /
            (name + tag + (tag.empty() ? "" : "_") + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

// A whole file as text (empty when it cannot be read).
inline std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void WriteText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

// Replaces line `line` (1-based) of a file.
inline void ReplaceLine(const std::filesystem::path& path, int line,
                        const std::string& replacement) {
  std::istringstream in(ReadText(path));
  std::string out, l;
  for (int i = 1; std::getline(in, l); ++i) out += (i == line ? replacement : l) + "\n";
  WriteText(path, out);
}

// Line `line` (1-based) of a file.
inline std::string Line(const std::filesystem::path& path, int line) {
  std::istringstream in(ReadText(path));
  std::string l;
  for (int i = 1; i <= line; ++i) std::getline(in, l);
  return l;
}

}  // namespace testing
}  // namespace io
}  // namespace plucker
