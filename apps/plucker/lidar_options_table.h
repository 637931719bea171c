// The options of `plucker lidar` in one table (lidar_options_table.cc, the mechanism of
// options_table.h): the YAML reader (`plucker lidar --config`), the defaults file
// config/lidar_default.yaml and the options table of docs/lidar-odometry.md all come from it.
// `plucker config lidar` prints the defaults file, `plucker config lidar --markdown` the
// documentation table; scripts/update_options.sh rewrites both, and app_options_table_test
// fails when either is stale.
//
// To add an option: one row in the table (key, unit, one-line doc, range, the member). To remove
// one: delete its row, then run scripts/update_options.sh.
#pragma once

#include <string>
#include <vector>

#include "options_table.h"
#include "plucker/lidar/odometry.h"

namespace plucker {
namespace app {

// Everything a `plucker lidar` config file sets.
struct LidarConfig {
  lidar::LidarOdometryOptions odometry;
  double map_voxel_size = 0.2;  // m, downsampling of --map
};

using LidarOption = OptionRow<LidarConfig>;
using LidarOptionsTable = OptionsTable<LidarConfig>;

// The table (options_table.h).
const LidarOptionsTable& LidarOptions();

// The rows, in the order of the defaults file. Keys are unique.
const std::vector<LidarOption>& LidarOptionTable();

// A YAML file setting every option to its value in `config`, with the groups and comments of
// config/lidar_default.yaml (which is LidarConfigYaml(LidarConfig())).
std::string LidarConfigYaml(const LidarConfig& config);

// The Markdown table of docs/lidar-odometry.md (key, type, default, range, unit, meaning).
std::string LidarOptionsMarkdown();

// Applies a YAML document to *config. Keys left out keep their value. Throws std::runtime_error
// naming `name` (the file) and the key for unknown keys, wrong types, values out of range and
// invalid YAML.
void ApplyLidarConfigYaml(const std::string& text, const std::string& name, LidarConfig* config);
// The same for a file (an empty file changes nothing).
void LoadLidarConfig(const std::string& path, LidarConfig* config);

}  // namespace app
}  // namespace plucker
