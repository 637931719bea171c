// The commands whose code reads images (OpenCV's image codecs and ximgproc pull in ~140 shared
// libraries, GDAL among them: 0.2 s of start-up) live in a module, plucker_vision_commands.so
// (vision_commands.cc), that `plucker` loads with dlopen only when the command line needs it, so
// that `plucker lidar` and every other command start without those libraries.
#pragma once

#include <CLI/CLI.hpp>

namespace plucker {
namespace app {

// True unless argv names a command that is registered in full already: the walk follows the
// words of argv down the registered subcommands and stops at the first one without subcommands
// (whose own options and arguments follow). It needs the module when it ends on a command that has
// subcommands (bare `plucker`, `plucker bench`, --help at such a level) or meets a word that is no
// registered subcommand there (an image command, or a typo: the error then lists every command).
bool NeedsVisionCommands(const CLI::App& app, int argc, const char* const* argv);

// Loads the module (beside the program, or in <libdir>/plucker when installed) and lets it
// register its commands in `app`. Returns false, after a warning on stderr naming the module and
// the loader's error, when it cannot be loaded (the other commands still work).
bool LoadVisionCommands(CLI::App& app, int* exit_code);

}  // namespace app
}  // namespace plucker
