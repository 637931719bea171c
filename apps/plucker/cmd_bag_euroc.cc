// `plucker bag from-euroc`: a EuRoC folder (what `plucker vio --euroc` reads) as a ROS 1 bag (or
// a ROS 2 .db3 when OUT ends in .db3) of
// sensor_msgs/Image (mono8, cam0) and sensor_msgs/Imu (imu0) messages. Part of the image module
// (it decodes the PNGs); added to the `bag` command of the main program.

#include <CLI/CLI.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <iostream>
#include <stdexcept>

#include "plucker/bag/bag_writer.h"
#include "plucker/io/euroc_dataset.h"
#include "run_guarded.h"

namespace plucker {
namespace app {
namespace {

struct FromEurocArgs {
  std::string data, out, image_topic = "/cam0/image_raw", imu_topic = "/imu0";
  std::string encoding = "mono8", compress;
  bool quiet = false;
};

// The gray image as `encoding` (mono8, bgr8, rgb8: the gray value in every channel; 16UC1: the
// value times 257, which plucker does not read: for testing that error).
std::vector<std::uint8_t> Encode(const cv::Mat& gray, const std::string& encoding) {
  const int channels = encoding == "mono8" ? 1 : encoding == "16UC1" ? 2 : 3;
  std::vector<std::uint8_t> out;
  out.reserve(gray.total() * channels);
  for (int r = 0; r < gray.rows; ++r) {
    for (int c = 0; c < gray.cols; ++c) {
      const std::uint8_t v = gray.at<std::uint8_t>(r, c);
      out.insert(out.end(), static_cast<std::size_t>(channels), v);
    }
  }
  return out;
}

int RunFromEuroc(const FromEurocArgs& a) {
  if (a.encoding != "mono8" && a.encoding != "bgr8" && a.encoding != "rgb8" &&
      a.encoding != "16UC1")
    throw std::runtime_error("--encoding must be mono8, bgr8, rgb8 or 16UC1, got '" + a.encoding +
                             "'");
  if (!a.compress.empty() && a.compress != "png" && a.compress != "jpeg")
    throw std::runtime_error("--compress must be png or jpeg, got '" + a.compress + "'");
  const io::EurocDataset euroc = io::ReadEurocDataset(a.data);
  bag::BagWriter writer(a.out);
  // Stamps are the folder's timestamps [ns] (header = receive): the reader's times are exact
  // nanosecond differences from the first IMU sample, so they are recovered by rounding.
  const std::int64_t origin = euroc.imu.origin_ns;
  auto ns = [origin](double t) { return origin + std::llround(t * 1e9); };
  for (const sensor::ImuSample& s : euroc.imu.imu)
    writer.WriteImuNs(a.imu_topic, std::max<std::int64_t>(ns(s.t), 1), ns(s.t), s);
  std::size_t images = 0;
  for (const io::EurocFrame& f : euroc.frames) {
    const cv::Mat gray = cv::imread(f.image, cv::IMREAD_GRAYSCALE);
    if (gray.empty()) {
      std::cerr << "plucker bag from-euroc: skipped " << f.image << ": not a readable image\n";
      continue;
    }
    const std::int64_t receive = std::max<std::int64_t>(ns(f.t), 1);
    if (!a.compress.empty()) {
      std::vector<std::uint8_t> bytes;
      cv::imencode("." + a.compress, gray, bytes);
      writer.WriteCompressedNs(a.image_topic, receive, ns(f.t), a.compress, bytes);
    } else {
      writer.WriteImageNs(a.image_topic, receive, ns(f.t), gray.cols, gray.rows, a.encoding,
                          Encode(gray, a.encoding));
    }
    ++images;
  }
  writer.Close();
  for (const io::FrameSkip& s : euroc.skipped) std::cerr << "  skipped " << s.ToString() << "\n";
  if (!a.quiet)
    std::cerr << "plucker bag from-euroc: " << images << " images on " << a.image_topic << ", "
              << euroc.imu.imu.size() << " IMU samples on " << a.imu_topic << " -> " << a.out
              << "\n";
  return 0;
}

}  // namespace

void RegisterBagFromEuroc(CLI::App& bag_cmd, int* exit_code) {
  auto args = std::make_shared<FromEurocArgs>();
  CLI::App* cmd = bag_cmd.add_subcommand(
      "from-euroc",
      "Write a EuRoC folder (cam0 + imu0) as sensor_msgs/Image (or CompressedImage) + Imu");
  cmd->add_option("data", args->data, "EuRoC folder (with mav0/)")->required();
  cmd->add_option("out", args->out, "Output .bag, or .db3 for a ROS 2 bag (not overwritten)")
      ->required();
  cmd->add_option("--image-topic", args->image_topic, "Default /cam0/image_raw");
  cmd->add_option("--imu-topic", args->imu_topic, "Default /imu0");
  cmd->add_option("--encoding", args->encoding,
                  "sensor_msgs/Image encoding: mono8 (default), bgr8, rgb8, 16UC1 (not read back)");
  cmd->add_option("--compress", args->compress,
                  "Write sensor_msgs/CompressedImage instead: png (lossless) or jpeg");
  cmd->add_flag("--quiet", args->quiet, "No summary");
  cmd->callback([args, exit_code]() {
    RunGuarded("bag from-euroc", exit_code, [&] { return RunFromEuroc(*args); });
  });
}

}  // namespace app
}  // namespace plucker
