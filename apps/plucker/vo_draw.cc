#include "vo_draw.h"

#include <cstdio>

#include "overlay.h"
#include "plucker/geometry/line_projection.h"
#include "plucker/io/image_folder.h"
#include "plucker/io/io_error.h"

namespace plucker {
namespace app {
namespace {

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
  cv::Mat canvas = overlay::Canvas(gray);
  const SE3d T_c_w = T_w_c.Inverse();
  for (const auto& s : frame.segments) {
    overlay::Segment(&canvas, s.s_px, s.e_px, overlay::kDetectedSegment, 1);
    const auto it = lines_w.find(s.line_id);
    if (it == lines_w.end()) continue;
    const Eigen::Vector3d l = ProjectLinePixels(K, TransformLine(T_c_w, it->second));
    if (!l.allFinite() || !(l.head<2>().norm() > 1e-12)) continue;
    overlay::Segment(&canvas, OntoLine(l, s.s_px), OntoLine(l, s.e_px), overlay::kReprojected, 2);
  }
  for (const auto& p : frame.points) {
    const bool landmark = points_w.count(p.point_id) > 0;
    overlay::Dot(&canvas, p.uv, landmark ? overlay::kLandmarkPoint : overlay::kTrackPoint);
  }
  return canvas;
}

void WriteFrameOverlay(const std::string& dir, const cv::Mat& gray,
                       const vision::Undistorter* undistorter, const PinholeIntrinsics& K,
                       const window::FrameInput& frame, int i, const SE3d& T_w_c,
                       const window::SlidingWindowEstimator& map) {
  const cv::Mat ideal = undistorter ? undistorter->Undistort(gray) : gray;
  const cv::Mat canvas = DrawVoFrame(ideal, K, frame, T_w_c, map.Points(), map.Lines());
  char name[32];
  std::snprintf(name, sizeof(name), "%06d.png", i);
  overlay::WriteImage(dir + "/" + name, canvas);
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
  WriteFrameOverlay(dir, gray, undistorter, K, frame, i, T_w_c, map);
}

}  // namespace app
}  // namespace plucker
