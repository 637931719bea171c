// plucker config vo|vio [--markdown] (see cmd_config.cc): in the vision module, as the tables
// name the odometry's options.
#include "commands.h"
#include "config_command.h"
#include "vio_config.h"
#include "vo_config.h"

namespace plucker {
namespace app {

void RegisterConfigVision(CLI::App& config_cmd, int* exit_code) {
  // vo: the defaults of a features folder; where --images differs, the image default in a note.
  AddConfigTable(
      &config_cmd, "vo", "docs/vo.md",
      [](bool md) {
        return md ? VoOptions().Markdown(FeaturesVoConfig(), VoImageDefaultNote)
                  : VoOptions().Yaml(FeaturesVoConfig(), VoImageDefaultNote);
      },
      exit_code);
  AddConfigTable(
      &config_cmd, "vio", "docs/vio.md",
      [](bool md) {
        return md ? VioOptions().Markdown(VioConfig()) : VioOptions().Yaml(VioConfig());
      },
      exit_code);
}

}  // namespace app
}  // namespace plucker
