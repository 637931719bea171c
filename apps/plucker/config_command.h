// One `plucker config <command> [--markdown]` subcommand: prints `print(markdown)`. Inline: the
// lidar table's is registered by the program (cmd_config.cc), those of vo and vio by the vision
// module (cmd_config_vision.cc), which cannot call into the program.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <iostream>
#include <memory>
#include <string>

namespace plucker {
namespace app {

inline void AddConfigTable(CLI::App* config_cmd, const std::string& name, const std::string& doc,
                           std::function<std::string(bool)> print, int* exit_code) {
  auto markdown = std::make_shared<bool>(false);
  CLI::App* sub = config_cmd->add_subcommand(
      name, "Every `plucker " + name + " --config` option with its default and range, as YAML");
  sub->add_flag("--markdown", *markdown, "The options as the Markdown table of " + doc);
  sub->callback([markdown, print, exit_code]() {
    std::cout << print(*markdown);
    *exit_code = std::cout ? 0 : 1;
  });
}

}  // namespace app
}  // namespace plucker
