// `plucker bag`: ROS 1 bags and ROS 2 .db3 bags without ROS (docs/bags.md). `bag info` lists what a
// bag holds (as `rosbag info`); `bag from-lidar` writes a LiDAR folder (KITTI, simulator, PCD) as a
// bag of PointCloud2 messages, so that `plucker lidar --bag` can be checked against `--data`.

#include <iomanip>
#include <iostream>
#include <sstream>

#include "commands.h"
#include "plucker/bag/bag_reader.h"
#include "plucker/bag/bag_writer.h"
#include "plucker/io/lidar_sequence.h"
#include "run_guarded.h"

namespace plucker {
namespace app {
namespace {

std::string Seconds(double t) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(6) << t;
  return s.str();
}

int RunInfo(const std::string& path) {
  const bag::BagReader reader(path);
  const bag::BagInfo& info = reader.info();
  std::cout << "path:     " << info.path << "\n"
            << "format:   " << info.format
            << (info.version == 200 ? " 2.0"
                : info.version > 0  ? " (other version)"
                                    : "")
            << "\n"
            << "size:     " << info.bytes << " bytes\n"
            << "duration: " << Seconds(info.end_s - info.start_s) << " s\n"
            << "start:    " << Seconds(info.start_s) << "\n"
            << "end:      " << Seconds(info.end_s) << "\n"
            << "messages: " << info.messages << "\n"
            << "topics:\n";
  for (const bag::TopicInfo& t : info.topics) {
    std::cout << "  " << t.topic << "  " << t.type << "  " << t.messages << " msgs  "
              << Seconds(t.first_s) << " .. " << Seconds(t.last_s) << "\n";
  }
  return 0;
}

struct FromLidarArgs {
  std::string data, sequence, out, topic = "/points";
  bool lz4 = false, quiet = false;
};

int RunFromLidar(const FromLidarArgs& a) {
  const io::LidarSequence seq = io::LidarSequence::Open(a.data, a.sequence);
  bag::BagWriterOptions options;
  options.lz4 = a.lz4;
  options.frame_id = "lidar";
  bag::BagWriter writer(a.out, options);
  LidarScan scan;
  std::size_t written = 0;
  for (std::size_t i = 0; i < seq.size(); ++i) {
    std::string error;
    if (!seq.Read(i, &scan, &error)) {
      std::cerr << "plucker bag from-lidar: skipped frame " << i << ": " << error << "\n";
      continue;
    }
    // The folder's frame time (times.txt, else 10 Hz) is the header stamp; the receive time
    // is the same (at least 1 ns: rosbag's minimum).
    const double t = i < seq.times().size() ? seq.times()[i] : 0.1 * static_cast<double>(i);
    writer.WriteScan(a.topic, std::max(t, 1e-9), t, scan);
    ++written;
    if (!a.quiet && (i % 100 == 99 || i + 1 == seq.size()))
      std::cerr << "\rframe " << (i + 1) << "/" << seq.size() << std::flush;
  }
  writer.Close();
  if (!a.quiet)
    std::cerr << "\nplucker bag from-lidar: " << written << " PointCloud2 messages on " << a.topic
              << " -> " << a.out << "\n";
  return 0;
}

}  // namespace

void RegisterBag(CLI::App& app, int* exit_code) {
  CLI::App* cmd = app.add_subcommand(
      "bag", "ROS 1 and ROS 2 (.db3) bags without ROS: info, write from folders");
  cmd->require_subcommand(1);

  auto path = std::make_shared<std::string>();
  CLI::App* info = cmd->add_subcommand("info", "Topics, types, counts and time spans of a bag");
  info->add_option("file", *path, "The .bag, .db3 or rosbag2 folder")->required();
  info->callback(
      [path, exit_code]() { RunGuarded("bag info", exit_code, [&] { return RunInfo(*path); }); });

  auto args = std::make_shared<FromLidarArgs>();
  CLI::App* from = cmd->add_subcommand(
      "from-lidar", "Write a LiDAR folder (what `plucker lidar --data` reads) as PointCloud2");
  from->add_option("data", args->data, "Sequence folder (KITTI, simulator, PCD)")->required();
  from->add_option("out", args->out, "Output .bag, or .db3 for a ROS 2 bag (not overwritten)")
      ->required();
  from->add_option("--sequence", args->sequence, "KITTI sequence under DATA/sequences");
  from->add_option("--topic", args->topic, "Topic name (default /points)");
  from->add_flag("--lz4", args->lz4, "LZ4-compressed chunks (ROS 1 bags)");
  from->add_flag("--quiet", args->quiet, "No progress output");
  from->callback([args, exit_code]() {
    RunGuarded("bag from-lidar", exit_code, [&] { return RunFromLidar(*args); });
  });
}

}  // namespace app
}  // namespace plucker
