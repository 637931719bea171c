// A real camera: pinhole intrinsics, a lens model and the image size. Two lens models:
//   kRadialTangential  `distortion` (geometry/distortion.h): plumb bob [k1, k2, p1, p2, k3], the
//                      default; all zero is the undistorted pinhole.
//   kEquidistant       `equidistant` (geometry/equidistant.h): Kannala-Brandt [k1, k2, k3, k4],
//                      Kalibr's pinhole-equi, for fisheye lenses. Never IsPinhole(), even with
//                      zero coefficients (theta_d = theta is not tan(theta)). Valid up to an
//                      angle of incidence of 90 deg or where theta_d stops increasing
//                      (EquidistantValidTheta); beyond it every conversion returns nullopt.
// Only the member of the selected model is used; the other is ignored. The image warp
// vision::Undistorter maps both (an equidistant camera with cv::fisheye::initUndistortRectifyMap:
// the same model and coefficient order, checked against cv::fisheye::projectPoints in
// io/kalibr_calibration_test.cc).
//
// Pixel coordinates and camera frame as in camera_rig.h (u right, v down, pixel centres at
// integers; z forward, x right, y down). Three kinds of 2D coordinates appear:
//   raw pixel            where the lens puts a point in the recorded image (distorted)
//   distorted normalized K^-1 * raw pixel
//   normalized (ideal)   x / z, y / z of the camera-frame point: what the factors use
// and "ideal pixel" = K * normalized, the pixel of an undistorted image with the same K.
//
// Models of the datasets (io/camera_calibration.h, io/kalibr_calibration.h read them):
//   KITTI (calib.txt P0)      images already rectified: undistorted pinhole (zero distortion)
//   Strecha (K.txt, .camera)  images already undistorted: undistorted pinhole
//   EuRoC (sensor.yaml)       raw images: pinhole + radial-tangential [k1, k2, p1, p2]
//   Kalibr (camchain.yaml)    pinhole + radtan or pinhole + equidistant
// Zero distortion is the undistorted pinhole; every conversion is then the identity on top of K.
//
// Segments are detected on undistorted images (vision/undistort.h warps the image once to the
// ideal pinhole), not on raw images with the endpoints undistorted afterwards: a straight 3D line
// images to a straight segment only under the ideal pinhole. Under radial distortion it bends
// into a curve, which a line detector splits into short fragments or fits with a chord that
// leaves the true curve by several pixels near the image border (EuRoC's k1 = -0.28 moves a
// corner pixel by tens of pixels). The point front end may work on either, converting with
// PixelToNormalized.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/distortion.h"
#include "plucker/geometry/equidistant.h"

namespace plucker {
namespace sensor {

enum class CameraModel { kRadialTangential, kEquidistant };

// "radtan" / "equidistant" (Kalibr's names), for messages and files.
const char* CameraModelName(CameraModel model);

struct Camera {
  PinholeIntrinsics K;
  RadTanDistortion distortion;  // kRadialTangential; all zero: undistorted pinhole
  int width = 0;
  int height = 0;
  CameraModel model = CameraModel::kRadialTangential;
  EquidistantDistortion equidistant;  // kEquidistant

  // Empty when the camera is usable, otherwise the first problem found (non-positive or
  // non-finite focal length, non-finite principal point or distortion, non-positive size).
  std::string Problem() const;
  bool IsValid() const { return Problem().empty(); }
  bool IsPinhole() const {  // no distortion
    return model == CameraModel::kRadialTangential && distortion.IsZero();
  }

  // Within [-margin, width - 1 + margin] x [-margin, height - 1 + margin].
  bool InImage(const Eigen::Vector2d& uv, double margin = 0.5) const;

  // Raw pixel -> ideal normalized coordinates: nullopt outside the valid region of the
  // distortion inverse (geometry/distortion.h, geometry/equidistant.h) or for non-finite input.
  std::optional<Eigen::Vector2d> PixelToNormalized(const Eigen::Vector2d& uv) const;
  // Raw pixel -> unit bearing in the camera frame (the same nullopt cases).
  std::optional<Eigen::Vector3d> PixelToBearing(const Eigen::Vector2d& uv) const;
  // Ideal normalized -> raw pixel (distorts). Equidistant: non-finite outside the valid region.
  Eigen::Vector2d NormalizedToPixel(const Eigen::Vector2d& xn) const;
  // Raw pixel <-> distorted normalized (K only).
  Eigen::Vector2d PixelToDistortedNormalized(const Eigen::Vector2d& uv) const {
    return K.ToNormalized<double>(uv);
  }
  Eigen::Vector2d DistortedNormalizedToPixel(const Eigen::Vector2d& xd) const {
    return K.ToPixel<double>(xd);
  }
  // Raw pixel <-> ideal pixel (same K); identities when IsPinhole().
  std::optional<Eigen::Vector2d> UndistortPixel(const Eigen::Vector2d& uv) const;
  std::optional<Eigen::Vector2d> DistortPixel(const Eigen::Vector2d& uv_ideal) const;

  // Raw pixel of a camera-frame point; nullopt when it is not in front (z <= min_depth) or,
  // equidistant, beyond the valid angle of incidence.
  std::optional<Eigen::Vector2d> Project(const Eigen::Vector3d& p_c, double min_depth = 1e-9) const;
  // The same with the 2x3 Jacobian d uv / d p_c (both models; the value equals Project's).
  std::optional<Eigen::Vector2d> ProjectWithJacobian(const Eigen::Vector3d& p_c,
                                                     Eigen::Matrix<double, 2, 3>* d_uv_d_p_c,
                                                     double min_depth = 1e-9) const;

  // The same camera without distortion (what the undistorted images show, with the same K).
  Camera Undistorted() const {
    Camera c = *this;
    c.distortion = RadTanDistortion{};
    c.model = CameraModel::kRadialTangential;
    c.equidistant = EquidistantDistortion{};
    return c;
  }
};

}  // namespace sensor
}  // namespace plucker
