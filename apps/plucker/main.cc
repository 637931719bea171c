#include <exception>
#include <iostream>

#include "commands.h"
#include "vision_module.h"

namespace plucker {
namespace app {
void RegisterBag(CLI::App& app, int* exit_code);  // cmd_bag.cc (ROS 1 bags)
}  // namespace app
}  // namespace plucker

int main(int argc, char** argv) {
  CLI::App app{"plucker: geometric features (points, lines, planes) for SLAM"};
  app.require_subcommand(1);
  int exit_code = 0;
  plucker::app::RegisterDemo(app, &exit_code);
  plucker::app::RegisterCheckJacobians(app, &exit_code);
  plucker::app::RegisterBench(app, &exit_code);
  plucker::app::RegisterSim(app, &exit_code);
  plucker::app::RegisterLidar(app, &exit_code);
  plucker::app::RegisterBag(app, &exit_code);
  plucker::app::RegisterEval(app, &exit_code);
  plucker::app::RegisterConfig(app, &exit_code);
  plucker::app::RegisterConvert(app, &exit_code);
  // The image commands (lines, vo, sfm, vio, bench lines, eval tracks; vision_commands.cc)
  // are a module loaded only when the command line needs it (vision_module.h).
  if (plucker::app::NeedsVisionCommands(app, argc, argv)) {
    plucker::app::LoadVisionCommands(app, &exit_code);
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::cerr << "plucker: error: " << e.what() << "\n";
    return 1;
  }
  return exit_code;
}
