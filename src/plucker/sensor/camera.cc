#include "plucker/sensor/camera.h"

#include <cmath>
#include <sstream>

namespace plucker {
namespace sensor {
namespace {

std::string Num(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

}  // namespace

std::string Camera::Problem() const {
  if (!std::isfinite(K.fx) || !(K.fx > 0)) return "focal length fx = " + Num(K.fx) + " is not > 0";
  if (!std::isfinite(K.fy) || !(K.fy > 0)) return "focal length fy = " + Num(K.fy) + " is not > 0";
  if (!std::isfinite(K.cx) || !std::isfinite(K.cy)) {
    return "principal point (" + Num(K.cx) + ", " + Num(K.cy) + ") is not finite";
  }
  if (!distortion.IsValid()) return "a distortion coefficient is not finite";
  if (width <= 0 || height <= 0) {
    return "image size " + std::to_string(width) + "x" + std::to_string(height) + " is not > 0";
  }
  return {};
}

bool Camera::InImage(const Eigen::Vector2d& uv, double margin) const {
  return uv.allFinite() && uv.x() >= -margin && uv.y() >= -margin && uv.x() <= width - 1 + margin &&
         uv.y() <= height - 1 + margin;
}

std::optional<Eigen::Vector2d> Camera::PixelToNormalized(const Eigen::Vector2d& uv) const {
  if (!K.IsValid() || !uv.allFinite()) return std::nullopt;
  return Undistort(distortion, K.ToNormalized<double>(uv));
}

Eigen::Vector2d Camera::NormalizedToPixel(const Eigen::Vector2d& xn) const {
  return K.ToPixel<double>(Distort(distortion, xn));
}

std::optional<Eigen::Vector2d> Camera::UndistortPixel(const Eigen::Vector2d& uv) const {
  return plucker::UndistortPixel(K, distortion, uv);
}

std::optional<Eigen::Vector2d> Camera::DistortPixel(const Eigen::Vector2d& uv_ideal) const {
  return plucker::DistortPixel(K, distortion, uv_ideal);
}

std::optional<Eigen::Vector2d> Camera::Project(const Eigen::Vector3d& p_c, double min_depth) const {
  if (!p_c.allFinite() || !(p_c.z() > min_depth)) return std::nullopt;
  const Eigen::Vector2d uv = NormalizedToPixel(p_c.head<2>() / p_c.z());
  if (!uv.allFinite()) return std::nullopt;
  return uv;
}

}  // namespace sensor
}  // namespace plucker
