// plucker config lidar|vo|vio [--markdown]: the options of a command from its one table
// (options_table.h): the defaults file config/<command>_default.yaml, or the Markdown table of
// its docs page. scripts/update_options.sh rewrites both from this output. `config vo` and
// `config vio` are registered by the vision module (cmd_config_vision.cc).
#include "commands.h"
#include "config_command.h"
#include "lidar_options_table.h"

namespace plucker {
namespace app {

void RegisterConfig(CLI::App& app, int* exit_code) {
  CLI::App* cmd = app.add_subcommand("config", "Print the default configuration of a command");
  cmd->require_subcommand(1);
  AddConfigTable(
      cmd, "lidar", "docs/lidar-odometry.md",
      [](bool md) { return md ? LidarOptionsMarkdown() : LidarConfigYaml(LidarConfig()); },
      exit_code);
}

}  // namespace app
}  // namespace plucker
