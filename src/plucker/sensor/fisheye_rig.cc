#include "plucker/sensor/fisheye_rig.h"

#include <cmath>
#include <stdexcept>

namespace plucker {
namespace sensor {

Camera RawCamera(const CameraRig& rig) {
  Camera c;
  c.K = rig.K;
  c.width = rig.width;
  c.height = rig.height;
  if (rig.fisheye) {
    c.model = CameraModel::kEquidistant;
    c.equidistant = rig.fisheye->coeffs;
  }
  return c;
}

Camera ViewCamera(const CameraRig& rig) {
  if (!rig.fisheye) return RawCamera(rig);
  Camera c;
  c.K = rig.fisheye->view_K;
  c.width = rig.fisheye->view_width;
  c.height = rig.fisheye->view_height;
  return c;
}

Eigen::Matrix2d RawFromViewJacobian(const Camera& raw, const Camera& view,
                                    const Eigen::Vector2d& uv_view) {
  const Eigen::Vector3d ray((uv_view.x() - view.K.cx) / view.K.fx,
                            (uv_view.y() - view.K.cy) / view.K.fy, 1.0);
  Eigen::Matrix<double, 2, 3> d_raw_d_ray;
  if (!raw.ProjectWithJacobian(ray, &d_raw_d_ray)) return Eigen::Matrix2d::Identity();
  Eigen::Matrix<double, 3, 2> d_ray_d_view = Eigen::Matrix<double, 3, 2>::Zero();
  d_ray_d_view(0, 0) = 1.0 / view.K.fx;
  d_ray_d_view(1, 1) = 1.0 / view.K.fy;
  return d_raw_d_ray * d_ray_d_view;
}

PinholeViewStats ToPinholeView(CameraImuSequence* sequence, double max_incidence_deg) {
  if (!(max_incidence_deg > 0.0 && max_incidence_deg <= 90.0)) {
    throw std::invalid_argument("ToPinholeView: max_incidence_deg must be in (0, 90]");
  }
  PinholeViewStats st;
  CameraRig& rig = sequence->rig;
  if (!rig.fisheye) return st;
  const Camera raw = RawCamera(rig), view = ViewCamera(rig);
  if (!raw.IsValid()) throw std::invalid_argument("fisheye camera: " + raw.Problem());
  if (!view.IsValid()) throw std::invalid_argument("fisheye view: " + view.Problem());
  const double min_cos = std::cos(max_incidence_deg * M_PI / 180.0);
  if (!rig.fisheye->points_in_view) {
    std::vector<PointObservation> kept;
    kept.reserve(sequence->points.size());
    for (PointObservation p : sequence->points) {
      const auto bearing = raw.PixelToBearing(p.uv);
      if (!bearing || !(bearing->z() > 0.0) || bearing->z() < min_cos) {
        ++st.dropped_points;
        continue;
      }
      p.uv = view.K.ToPixel<double>(bearing->head<2>() / bearing->z());
      p.uv_velocity.reset();  // a raw-pixel velocity is not one of the view
      p.sqrt_info_scale = RawFromViewJacobian(raw, view, p.uv);
      kept.push_back(p);
      ++st.converted_points;
    }
    sequence->points = std::move(kept);
  }
  rig.K = view.K;
  rig.width = view.width;
  rig.height = view.height;
  rig.fisheye.reset();
  return st;
}

}  // namespace sensor
}  // namespace plucker
