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

const char* CameraModelName(CameraModel model) {
  switch (model) {
    case CameraModel::kRadialTangential:
      return "radtan";
    case CameraModel::kEquidistant:
      return "equidistant";
  }
  return "unknown";
}

std::string Camera::Problem() const {
  if (!std::isfinite(K.fx) || !(K.fx > 0)) return "focal length fx = " + Num(K.fx) + " is not > 0";
  if (!std::isfinite(K.fy) || !(K.fy > 0)) return "focal length fy = " + Num(K.fy) + " is not > 0";
  if (!std::isfinite(K.cx) || !std::isfinite(K.cy)) {
    return "principal point (" + Num(K.cx) + ", " + Num(K.cy) + ") is not finite";
  }
  if (model == CameraModel::kEquidistant) {
    if (!equidistant.IsValid()) return "an equidistant distortion coefficient is not finite";
  } else if (model != CameraModel::kRadialTangential) {
    return "unknown camera model";
  } else if (!distortion.IsValid()) {
    return "a distortion coefficient is not finite";
  }
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
  if (model == CameraModel::kEquidistant) {
    return EquidistantUndistort(equidistant, K.ToNormalized<double>(uv));
  }
  return Undistort(distortion, K.ToNormalized<double>(uv));
}

std::optional<Eigen::Vector3d> Camera::PixelToBearing(const Eigen::Vector2d& uv) const {
  if (!K.IsValid() || !uv.allFinite()) return std::nullopt;
  if (model == CameraModel::kEquidistant) {
    return EquidistantUnprojectBearing(equidistant, K.ToNormalized<double>(uv));
  }
  const auto xn = Undistort(distortion, K.ToNormalized<double>(uv));
  if (!xn) return std::nullopt;
  return Eigen::Vector3d(xn->x(), xn->y(), 1.0).normalized();
}

Eigen::Vector2d Camera::NormalizedToPixel(const Eigen::Vector2d& xn) const {
  if (model == CameraModel::kEquidistant) {
    const auto xd = EquidistantProject(equidistant, Eigen::Vector3d(xn.x(), xn.y(), 1.0));
    return xd ? K.ToPixel<double>(*xd) : Eigen::Vector2d::Constant(std::nan(""));
  }
  return K.ToPixel<double>(Distort(distortion, xn));
}

std::optional<Eigen::Vector2d> Camera::UndistortPixel(const Eigen::Vector2d& uv) const {
  if (model == CameraModel::kEquidistant) {
    const auto xn = PixelToNormalized(uv);
    if (!xn) return std::nullopt;
    return K.ToPixel<double>(*xn);
  }
  return plucker::UndistortPixel(K, distortion, uv);
}

std::optional<Eigen::Vector2d> Camera::DistortPixel(const Eigen::Vector2d& uv_ideal) const {
  if (model == CameraModel::kEquidistant) {
    if (!K.IsValid() || !uv_ideal.allFinite()) return std::nullopt;
    const Eigen::Vector2d uv = NormalizedToPixel(K.ToNormalized<double>(uv_ideal));
    if (!uv.allFinite()) return std::nullopt;
    return uv;
  }
  return plucker::DistortPixel(K, distortion, uv_ideal);
}

std::optional<Eigen::Vector2d> Camera::Project(const Eigen::Vector3d& p_c, double min_depth) const {
  if (!p_c.allFinite() || !(p_c.z() > min_depth)) return std::nullopt;
  if (model == CameraModel::kEquidistant) {
    const auto xd = EquidistantProject(equidistant, p_c);
    if (!xd) return std::nullopt;
    return K.ToPixel<double>(*xd);
  }
  const Eigen::Vector2d uv = NormalizedToPixel(p_c.head<2>() / p_c.z());
  if (!uv.allFinite()) return std::nullopt;
  return uv;
}

std::optional<Eigen::Vector2d> Camera::ProjectWithJacobian(const Eigen::Vector3d& p_c,
                                                           Eigen::Matrix<double, 2, 3>* d_uv_d_p_c,
                                                           double min_depth) const {
  if (!p_c.allFinite() || !(p_c.z() > min_depth)) return std::nullopt;
  Eigen::Matrix<double, 2, 3> d_xd_d_p;
  Eigen::Vector2d xd;
  if (model == CameraModel::kEquidistant) {
    const auto e = EquidistantProject(equidistant, p_c, &d_xd_d_p);
    if (!e) return std::nullopt;
    xd = *e;
  } else {
    const double inv_z = 1.0 / p_c.z();
    const Eigen::Vector2d xn = p_c.head<2>() / p_c.z();
    Eigen::Matrix<double, 2, 3> d_xn_d_p;
    d_xn_d_p << inv_z, 0.0, -xn.x() * inv_z, 0.0, inv_z, -xn.y() * inv_z;
    Eigen::Matrix2d d_xd_d_xn;
    xd = Distort(distortion, xn, &d_xd_d_xn);
    d_xd_d_p = d_xd_d_xn * d_xn_d_p;
  }
  const Eigen::Vector2d uv = K.ToPixel<double>(xd);
  if (!uv.allFinite()) return std::nullopt;
  if (d_uv_d_p_c) {
    *d_uv_d_p_c = d_xd_d_p;
    d_uv_d_p_c->row(0) *= K.fx;
    d_uv_d_p_c->row(1) *= K.fy;
  }
  return uv;
}

}  // namespace sensor
}  // namespace plucker
