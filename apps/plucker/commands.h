// Subcommands of the `plucker` program. Each Register* adds one subcommand (with --help) to the
// app; its callback stores the process exit code in *exit_code. Errors reach the user as
// "plucker <cmd>: error: <file>: <problem>" and a non-zero exit code, never a crash.
#pragma once

#include <CLI/CLI.hpp>

namespace plucker {
namespace app {

void RegisterDemo(CLI::App& app, int* exit_code);            // cmd_demo.cc
void RegisterCheckJacobians(CLI::App& app, int* exit_code);  // cmd_check_jacobians.cc
void RegisterBench(CLI::App& app, int* exit_code);           // cmd_bench.cc
void RegisterSim(CLI::App& app, int* exit_code);             // cmd_sim.cc
void RegisterLidar(CLI::App& app, int* exit_code);           // cmd_lidar.cc
void RegisterEval(CLI::App& app, int* exit_code);            // cmd_eval.cc
void AddEvalImu(CLI::App* eval_cmd, int* exit_code);         // cmd_eval_imu.cc, `eval imu`
void AddEvalInit(CLI::App* eval_cmd, int* exit_code);        // cmd_eval_init.cc, `eval init`
void RegisterConfig(CLI::App& app, int* exit_code);          // cmd_config.cc
void RegisterConvert(CLI::App& app, int* exit_code);         // cmd_convert.cc
void RegisterLines(CLI::App& app, int* exit_code);           // cmd_lines.cc
void RegisterEvalLines(CLI::App& eval, int* exit_code);      // cmd_eval_lines.cc (eval lines)
void AddLinesTrack(CLI::App* lines, int* exit_code);      // cmd_lines_track.cc (lines match|track)
void RegisterEvalTracks(CLI::App& eval, int* exit_code);  // cmd_lines_track.cc (eval tracks)
void RegisterVo(CLI::App& app, int* exit_code);           // cmd_vo.cc
void RegisterVio(CLI::App& app, int* exit_code);          // cmd_vio.cc
void RegisterSfm(CLI::App& app, int* exit_code);          // cmd_sfm.cc
void RegisterEvalSfm(CLI::App& eval, int* exit_code);     // cmd_eval_sfm.cc (eval sfm)
void RegisterEvalLidarBasin(CLI::App& eval, int* exit_code);  // cmd_eval_lidar_basin.cc

// `bench lines`, added by the vision module (vision_commands.cc), as the image commands above.
void RegisterBenchLines(CLI::App& bench, int* exit_code);  // cmd_bench_lines.cc

}  // namespace app
}  // namespace plucker
