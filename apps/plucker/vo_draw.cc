#include "vo_draw.h"

#include <cstdio>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "plucker/io/image_folder.h"
#include "plucker/io/io_error.h"

#include "plucker/geometry/line_projection.h"

namespace plucker {
namespace app {
namespace {

cv::Point2d Px(const Eigen::Vector2d& p) { return {p.x(), p.y()}; }

// p projected onto the image line l (l1 x + l2 y + l3 = 0).
Eigen::Vector2d OntoLine(const Eigen::Vector3d& l, const Eigen::Vector2d& p) {
  const Eigen::Vector2d n = l.head<2>();
  return p - (n.dot(p) + l.z()) / n.squaredNorm() * n;
}

}  // namespace

cv::Mat DrawVoFrame(const cv::Mat& gray, const PinholeIntrinsics& K,
                    const window::FrameInput& frame, const SE3d& T_w_c,
                    const std::map<int, Eigen::Vector3d>& points_w,
                    const std::map<int, Line6d>& lines_w) {
  cv::Mat canvas;
  cv::cvtColor(gray, canvas, cv::COLOR_GRAY2BGR);
  const SE3d T_c_w = T_w_c.Inverse();
  for (const auto& s : frame.segments) {
    cv::line(canvas, Px(s.s_px), Px(s.e_px), cv::Scalar(255, 128, 0), 1, cv::LINE_AA);
    const auto it = lines_w.find(s.line_id);
    if (it == lines_w.end()) continue;
    const Eigen::Vector3d l = ProjectLinePixels(K, TransformLine(T_c_w, it->second));
    if (!l.allFinite() || !(l.head<2>().norm() > 1e-12)) continue;
    cv::line(canvas, Px(OntoLine(l, s.s_px)), Px(OntoLine(l, s.e_px)), cv::Scalar(0, 0, 255), 2,
             cv::LINE_AA);
  }
  for (const auto& p : frame.points) {
    const bool landmark = points_w.count(p.point_id) > 0;
    cv::circle(canvas, Px(p.uv), 2, landmark ? cv::Scalar(0, 220, 0) : cv::Scalar(0, 220, 220), -1,
               cv::LINE_AA);
  }
  return canvas;
}

void WriteVoOverlay(const std::string& dir, const std::string& image,
                    const vision::Undistorter* undistorter, const PinholeIntrinsics& K,
                    const window::FrameInput& frame, int i, const SE3d& T_w_c,
                    const window::SlidingWindowEstimator& map) {
  cv::Mat gray;
  try {
    gray = io::ReadGrayImage(image);
  } catch (const io::IoError&) {
    return;  // skipped image: already warned about
  }
  if (undistorter) gray = undistorter->Undistort(gray);
  const cv::Mat canvas = DrawVoFrame(gray, K, frame, T_w_c, map.Points(), map.Lines());
  char name[32];
  std::snprintf(name, sizeof(name), "%06d.png", i);
  const std::string out = dir + "/" + name;
  if (!cv::imwrite(out, canvas)) throw io::IoError(out, "cannot write the overlay image");
}

}  // namespace app
}  // namespace plucker
