// Command-line flags that set an option of a command's table (options_table.h): one code path
// with --config. The file is read first, then each flag given on the command line sets its key
// through the table (the same type and range checks; an error names the flag and the key).
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "options_table.h"

namespace plucker {
namespace app {

struct OptionFlag {
  const CLI::Option* flag;
  std::string key;    // the option it sets
  std::string value;  // for flags without a value ("false" for --no-lines); empty: the flag's
};

// Applies the flags that were given, in order.
template <typename Config>
void ApplyOptionFlags(const OptionsTable<Config>& table, const std::vector<OptionFlag>& flags,
                      Config* config) {
  for (const OptionFlag& f : flags) {
    if (f.flag->count() == 0) continue;
    const std::string value = f.value.empty() ? f.flag->as<std::string>() : f.value;
    table.Set(f.key, value, f.flag->get_name(), config);
  }
}

}  // namespace app
}  // namespace plucker
