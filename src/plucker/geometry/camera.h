// Pinhole camera intrinsics (zero skew). Distortion lives in geometry/distortion.h; observations
// are undistorted before they reach the residuals, which use this ideal pinhole model.
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace plucker {

struct PinholeIntrinsics {
  double fx = 1.0, fy = 1.0, cx = 0.0, cy = 0.0;

  Eigen::Matrix3d K() const {
    Eigen::Matrix3d k;
    k << fx, 0, cx, 0, fy, cy, 0, 0, 1;
    return k;
  }
  bool IsValid() const {
    return std::isfinite(fx) && std::isfinite(fy) && std::isfinite(cx) && std::isfinite(cy) &&
           fx > 0 && fy > 0;
  }
  // Normalized image coordinates -> pixels.
  template <typename T>
  Eigen::Matrix<T, 2, 1> ToPixel(const Eigen::Matrix<T, 2, 1>& xn) const {
    return Eigen::Matrix<T, 2, 1>(T(fx) * xn(0) + T(cx), T(fy) * xn(1) + T(cy));
  }
  // Pixels -> normalized image coordinates.
  template <typename T>
  Eigen::Matrix<T, 2, 1> ToNormalized(const Eigen::Matrix<T, 2, 1>& uv) const {
    return Eigen::Matrix<T, 2, 1>((uv(0) - T(cx)) / T(fx), (uv(1) - T(cy)) / T(fy));
  }
};

}  // namespace plucker
