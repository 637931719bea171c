// Fisheye rigs (camera_rig.h FisheyeView) as the feature pipelines take them. The window and the
// two-view start work in the pixels of one pinhole K; a fisheye sequence (the simulator's
// `--camera-model kb`) gives its segments in an undistorted pinhole view and its points either in
// that view or as raw pixels of the full fisheye image. ToPinholeView maps the raw points
// through the Kannala-Brandt model (sensor::Camera::PixelToNormalized, the inverse of the lens)
// to normalized coordinates and then into the view's pixels (the view K), so every observation
// is in the view's pinhole; points beyond the lens's valid angle or max_incidence_deg are
// dropped. Points far off-axis land outside the view's image (a pinhole pixel of an angle of
// incidence theta lies at f tan(theta)): that is what keeps the full field of view.
#pragma once

#include "plucker/sensor/camera.h"
#include "plucker/sensor/camera_imu_sequence.h"
#include "plucker/sensor/camera_rig.h"

namespace plucker {
namespace sensor {

// The raw camera of a rig: the Kannala-Brandt camera of a fisheye rig, else the pinhole K.
Camera RawCamera(const CameraRig& rig);
// The pinhole view of a fisheye rig's segments (the rig's own pinhole when it has none).
Camera ViewCamera(const CameraRig& rig);

struct PinholeViewStats {
  int converted_points = 0;  // raw fisheye pixels mapped into the view
  int dropped_points = 0;    // beyond the valid angle or max_incidence_deg
};

// The default of ToPinholeView: raw points up to 60 deg off the axis. A raw pixel's noise grows
// in the view by up to 1 / cos^2(theta) radially (4x at 60 deg); each mapped point carries that
// as its PointObservation::sqrt_info_scale (RawFromViewJacobian), which the window weighs it by.
constexpr double kDefaultMaxIncidenceDeg = 60.0;

// d raw pixel / d view pixel at a view pixel (identity where the raw camera cannot project it):
// the square-root information of a raw point mapped into the view, relative to its raw noise.
Eigen::Matrix2d RawFromViewJacobian(const Camera& raw, const Camera& view,
                                    const Eigen::Vector2d& uv_view);

// Rewrites the sequence in the view's pinhole: points mapped (raw points) and the rig replaced
// by ViewCamera's K and size (fisheye cleared, T_b_c kept). A pinhole sequence is unchanged.
// Outliers (id -1) are mapped alike. Throws std::invalid_argument for an invalid view or
// max_incidence_deg not in (0, 90].
PinholeViewStats ToPinholeView(CameraImuSequence* sequence,
                               double max_incidence_deg = kDefaultMaxIncidenceDeg);

}  // namespace sensor
}  // namespace plucker
