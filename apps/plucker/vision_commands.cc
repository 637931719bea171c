// The entry point of the module plucker_vision_commands.so (see vision_module.h): the commands
// and subcommands whose code reads images. A new image command: its source files go into
// plucker_vision_sources (CMakeLists.txt here) and its Register* call below.
#include <CLI/CLI.hpp>

#include "commands.h"

namespace plucker {
namespace app {
void RegisterBagFromEuroc(CLI::App& bag_cmd, int* exit_code);     // cmd_bag_euroc.cc
void RegisterConfigVision(CLI::App& config_cmd, int* exit_code);  // cmd_config_vision.cc
}  // namespace app
}  // namespace plucker

extern "C" void PluckerRegisterVisionCommands(CLI::App* app, int* exit_code) {
  using namespace plucker::app;
  RegisterLines(*app, exit_code);
  RegisterVo(*app, exit_code);
  RegisterSfm(*app, exit_code);
  RegisterVio(*app, exit_code);
  RegisterBenchLines(*app->get_subcommand("bench"), exit_code);
  RegisterEvalTracks(*app->get_subcommand("eval"), exit_code);
  RegisterBagFromEuroc(*app->get_subcommand("bag"), exit_code);
  RegisterConfigVision(*app->get_subcommand("config"), exit_code);
}
