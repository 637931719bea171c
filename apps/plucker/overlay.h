// The one palette and drawing helper of the program's overlays (`plucker vo --draw`,
// `plucker lines detect|match --draw`, `plucker sfm` overlays). Colours by role, BGR:
//   kDetectedSegment (blue):      a detected or tracked image segment;
//   kReconstructedSegment (green): a segment observing a reconstructed 3D line;
//   kReprojected (red):           a 3D line (or segment) reprojected with the view's pose;
//   kLandmarkPoint (green dot):   a point track with a landmark;
//   kTrackPoint (yellow dot):     a point track without one;
//   TrackColour(id):              one colour per track or match (pairs drawn side by side).
#pragma once

#include <string>

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>  // cv::LINE_AA

namespace plucker {
namespace app {
namespace overlay {

inline const cv::Scalar kDetectedSegment(255, 128, 0);
inline const cv::Scalar kReconstructedSegment(0, 200, 0);
inline const cv::Scalar kReprojected(0, 0, 255);
inline const cv::Scalar kLandmarkPoint(0, 220, 0);
inline const cv::Scalar kTrackPoint(0, 220, 220);

// A distinct, repeatable colour per id.
cv::Scalar TrackColour(int id);

// The 8-bit gray image as BGR, scaled by `scale` (area interpolation) when it is not 1.
cv::Mat Canvas(const cv::Mat& gray, double scale = 1.0);

// Segment a-b (pixels, multiplied by scale; anti-aliased unless line_type says otherwise) and
// filled anti-aliased dot.
void Segment(cv::Mat* canvas, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
             const cv::Scalar& colour, int thickness, double scale = 1.0,
             int line_type = cv::LINE_AA);
void Dot(cv::Mat* canvas, const Eigen::Vector2d& p, const cv::Scalar& colour, int radius = 2);

// Writes the image (the format from the extension); throws io::IoError naming the file when
// OpenCV cannot (folder missing, unknown extension).
void WriteImage(const std::string& path, const cv::Mat& canvas);

}  // namespace overlay
}  // namespace app
}  // namespace plucker
