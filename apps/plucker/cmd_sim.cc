#include "commands.h"

namespace plucker {
namespace app {

void RegisterSimCamera(CLI::App& sim, int* exit_code);  // cmd_sim_camera.cc
void RegisterSimLidar(CLI::App& sim, int* exit_code);   // cmd_sim_lidar.cc

void RegisterSim(CLI::App& app, int* exit_code) {
  CLI::App* sim = app.add_subcommand("sim", "Simulate sensor data with ground truth");
  sim->require_subcommand(1);
  RegisterSimCamera(*sim, exit_code);
  RegisterSimLidar(*sim, exit_code);
}

}  // namespace app
}  // namespace plucker
