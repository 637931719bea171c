#include "vision_module.h"

#include <dlfcn.h>

#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace plucker {
namespace app {
namespace {

bool HasSubcommands(const CLI::App& level) {
  return !level.get_subcommands([](const CLI::App*) { return true; }).empty();
}

// The registered subcommand of `level` called `word`, or nullptr.
const CLI::App* FindSubcommand(const CLI::App& level, const std::string& word) {
  const auto found =
      level.get_subcommands([&word](const CLI::App* sub) { return sub->check_name(word); });
  return found.empty() ? nullptr : found.front();
}

bool IsHelpFlag(const std::string& word) {
  return word == "-h" || word == "--help" || word == "--help-all";
}

// Where the module may be: beside the program (build tree), then <prefix>/<libdir>/plucker
// (installed; PLUCKER_MODULE_DIR_FROM_BIN is that folder relative to <prefix>/<bindir>).
std::vector<std::filesystem::path> ModuleCandidates() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::filesystem::path bin_dir = ec ? std::filesystem::path(".") : exe.parent_path();
  return {bin_dir / PLUCKER_VISION_MODULE,
          bin_dir / PLUCKER_MODULE_DIR_FROM_BIN / PLUCKER_VISION_MODULE};
}

}  // namespace

bool NeedsVisionCommands(const CLI::App& app, int argc, const char* const* argv) {
  const CLI::App* level = &app;
  for (int i = 1; i < argc; ++i) {
    if (!HasSubcommands(*level)) return false;
    const std::string word = argv[i];
    if (IsHelpFlag(word)) return true;
    if (!word.empty() && word[0] == '-') continue;
    level = FindSubcommand(*level, word);
    if (level == nullptr) return true;
  }
  return HasSubcommands(*level);
}

bool LoadVisionCommands(CLI::App& app, int* exit_code) {
  std::string errors;
  for (const std::filesystem::path& path : ModuleCandidates()) {
    if (!std::filesystem::exists(path)) continue;
    // Never closed: the commands' callbacks are code of the module.
    void* module = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (module == nullptr) {
      errors += std::string("; ") + dlerror();
      continue;
    }
    using RegisterFn = void (*)(CLI::App*, int*);
    auto register_commands =
        reinterpret_cast<RegisterFn>(dlsym(module, "PluckerRegisterVisionCommands"));
    if (register_commands == nullptr) {
      errors += "; " + path.string() + ": no PluckerRegisterVisionCommands";
      continue;
    }
    register_commands(&app, exit_code);
    return true;
  }
  std::cerr
      << "plucker: warning: the image commands (lines, vo, sfm, vio, bench lines, eval tracks) are "
         "unavailable: cannot load "
      << PLUCKER_VISION_MODULE << " beside the program or in "
      << ModuleCandidates().back().parent_path().string()
      << (errors.empty() ? std::string(" (not found)") : errors) << "\n";
  return false;
}

}  // namespace app
}  // namespace plucker
