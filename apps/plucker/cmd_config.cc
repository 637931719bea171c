// plucker config lidar [--markdown]: the options of `plucker lidar` from their one table
// (lidar_options_table.h): the defaults file config/lidar_default.yaml, or the Markdown table of
// docs/lidar-odometry.md. scripts/update_lidar_options.sh rewrites both from this output.
#include <iostream>
#include <memory>

#include "commands.h"
#include "lidar_options_table.h"

namespace plucker {
namespace app {

void RegisterConfig(CLI::App& app, int* exit_code) {
  CLI::App* cmd = app.add_subcommand("config", "Print the default configuration of a command");
  cmd->require_subcommand(1);
  auto markdown = std::make_shared<bool>(false);
  CLI::App* lidar = cmd->add_subcommand(
      "lidar", "Every `plucker lidar --config` option with its default, as YAML");
  lidar->add_flag("--markdown", *markdown,
                  "The options as the Markdown table of docs/lidar-odometry.md instead");
  lidar->callback([markdown, exit_code]() {
    std::cout << (*markdown ? LidarOptionsMarkdown() : LidarConfigYaml(LidarConfig()));
    *exit_code = std::cout ? 0 : 1;
  });
}

}  // namespace app
}  // namespace plucker
