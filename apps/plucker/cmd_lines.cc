// `plucker lines detect`: line segments of one image or of every image of a folder.
//   plucker lines detect --image IMG [--out segs.txt] [--draw out.png] [options]
//   plucker lines detect --images DIR --out OUTDIR [--draw DRAWDIR] [options]
// Output files hold `x1 y1 x2 y2` per line (io/segments.h) after '#' comments that name the
// method and the image and record `# detection_ms <ms>`, the time of DetectLineSegments alone
// (no reading or writing), which `plucker eval lines` reports. In folder mode an unreadable
// image is skipped with a warning naming it; the command fails only when no image is processed.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "commands.h"
#include "overlay.h"
#include "plucker/io/image_folder.h"
#include "plucker/io/io_error.h"
#include "plucker/io/segments.h"
#include "plucker/vision/line_detector.h"
#include "run_guarded.h"

namespace plucker {
namespace app {
namespace {

namespace fs = std::filesystem;

struct DetectArgs {
  std::string image, images, out, draw, method = "edlines-refined";
  double min_length = 0.0;
  bool quiet = false;
};

std::string Number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", v);
  return buf;
}

struct Detected {
  vision::LineDetection detection;
  double ms = 0.0;
  cv::Size size;
};

Detected DetectFile(const std::string& path, const vision::LineDetectorOptions& options) {
  Detected d;
  const cv::Mat gray = io::ReadGrayImage(path);
  d.size = gray.size();
  const auto start = std::chrono::steady_clock::now();
  d.detection = vision::DetectLineSegments(gray, options);
  d.ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return d;
}

void WriteOutput(const std::string& out, const std::string& image, const DetectArgs& a,
                 const Detected& d) {
  io::SegmentFile file;
  file.segments = d.detection.segments;
  file.detection_ms = d.ms;
  const std::vector<std::string> header = {
      "plucker lines detect --method " + a.method + " --min-length " + Number(a.min_length),
      "image " + image + " (" + std::to_string(d.size.width) + "x" + std::to_string(d.size.height) +
          "), " + std::to_string(file.segments.size()) + " segments x1 y1 x2 y2 [px]"};
  if (out.empty()) {
    std::cout << io::FormatSegments(file, header);
  } else {
    io::WriteSegments(out, file, header);
  }
}

// The image in colour with the detected segments (overlay.h's palette).
void Draw(const std::string& image, const std::vector<vision::Segment2d>& segments,
          const std::string& out) {
  cv::Mat canvas = cv::imread(image, cv::IMREAD_COLOR);
  if (canvas.empty()) throw io::IoError(image, "cannot decode the image");
  for (const vision::Segment2d& s : segments)
    overlay::Segment(&canvas, s.head<2>(), s.tail<2>(), overlay::kDetectedSegment, 1);
  overlay::WriteImage(out, canvas);
}

vision::LineDetectorOptions Options(const DetectArgs& a) {
  vision::LineDetectorOptions options;
  const std::optional<vision::LineMethod> method = vision::ParseLineMethod(a.method);
  if (!method) {
    throw std::invalid_argument("--method " + a.method + ": expected one of " +
                                vision::LineMethodNames());
  }
  options.method = *method;
  options.min_length = a.min_length;
  return options;
}

void MakeFolder(const std::string& dir, const char* flag) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir, ec)) {
    throw io::IoError(dir, std::string("cannot create the ") + flag + " folder");
  }
}

int RunSingle(const DetectArgs& a, const vision::LineDetectorOptions& options) {
  const Detected d = DetectFile(a.image, options);
  WriteOutput(a.out, a.image, a, d);
  if (!a.draw.empty()) Draw(a.image, d.detection.segments, a.draw);
  if (!a.quiet && !a.out.empty()) {
    std::printf("%s: %zu segments in %.1f ms -> %s\n", a.image.c_str(), d.detection.segments.size(),
                d.ms, a.out.c_str());
  }
  return 0;
}

int RunFolder(const DetectArgs& a, const vision::LineDetectorOptions& options) {
  if (a.out.empty()) throw std::invalid_argument("--images needs --out OUTDIR");
  const std::vector<std::string> files = io::ListImageFiles(a.images);
  if (files.empty()) throw io::IoError(a.images, "no image files in the folder");
  MakeFolder(a.out, "--out");
  if (!a.draw.empty()) MakeFolder(a.draw, "--draw");
  int done = 0, skipped = 0;
  double total_ms = 0.0;
  for (std::size_t i = 0; i < files.size(); ++i) {
    const std::string stem = fs::path(files[i]).stem().string();
    try {
      const Detected d = DetectFile(files[i], options);
      WriteOutput((fs::path(a.out) / (stem + ".txt")).string(), files[i], a, d);
      if (!a.draw.empty()) {
        Draw(files[i], d.detection.segments, (fs::path(a.draw) / (stem + ".png")).string());
      }
      ++done;
      total_ms += d.ms;
      if (!a.quiet) {
        std::printf("[%zu/%zu] %s: %zu segments, %.1f ms\n", i + 1, files.size(),
                    fs::path(files[i]).filename().c_str(), d.detection.segments.size(), d.ms);
      }
    } catch (const io::IoError& e) {
      ++skipped;
      std::fflush(stdout);
      std::cerr << "plucker lines detect: warning: " << e.what() << " (skipped)\n";
    }
  }
  if (done == 0) throw io::IoError(a.images, "no image could be read");
  if (!a.quiet) {
    std::printf("%d images, %d skipped, %.1f ms per image (detection only) -> %s\n", done, skipped,
                total_ms / done, a.out.c_str());
  }
  return 0;
}

int RunDetect(const DetectArgs& a) {
  if (a.image.empty() == a.images.empty()) {
    throw std::invalid_argument("give exactly one of --image IMG or --images DIR");
  }
  if (!(a.min_length >= 0.0)) throw std::invalid_argument("--min-length must be >= 0");
  const vision::LineDetectorOptions options = Options(a);
  return a.image.empty() ? RunFolder(a, options) : RunSingle(a, options);
}

}  // namespace

void RegisterLines(CLI::App& app, int* exit_code) {
  CLI::App* lines = app.add_subcommand("lines", "Line segments on real images");
  lines->require_subcommand(1);
  auto a = std::make_shared<DetectArgs>();
  CLI::App* detect = lines->add_subcommand(
      "detect", "Detect line segments (x1 y1 x2 y2 per line) in an image or a folder of images");
  detect->add_option("--image", a->image, "One image");
  detect->add_option("--images", a->images,
                     "A folder: its image files in name order (other files are ignored)");
  detect->add_option("--out", a->out,
                     "Segment file (--image; default: standard output) or folder of <name>.txt "
                     "(--images, required)");
  detect->add_option("--draw", a->draw,
                     "Draw the segments: an image file (--image) or a folder of <name>.png "
                     "(--images)");
  detect->add_option("--method", a->method, vision::LineMethodNames())->capture_default_str();
  detect->add_option("--min-length", a->min_length, "Drop segments shorter than this [px]")
      ->capture_default_str();
  detect->add_flag("--quiet", a->quiet, "No progress lines (warnings and errors still print)");
  detect->callback(
      [a, exit_code] { RunGuarded("lines detect", exit_code, [&] { return RunDetect(*a); }); });
  AddLinesTrack(lines, exit_code);  // lines match, lines track (cmd_lines_track.cc)
}

}  // namespace app
}  // namespace plucker
