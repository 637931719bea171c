// Jacobian checks of the camera models: geometry/equidistant.h (Kannala-Brandt) and
// sensor::Camera::ProjectWithJacobian for both models (pixels w.r.t. the camera-frame point).
#include <cmath>
#include <string>

#include "plucker/geometry/equidistant.h"
#include "plucker/sensor/camera.h"
#include "plucker/verify/checks.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace verify {

namespace {

// Fisheye coefficients of the size calibrated lenses have (TUM-VI's are within these ranges).
EquidistantDistortion RandomEquidistant(Rng& rng) {
  EquidistantDistortion D;
  D.k1 = Uniform(rng, -0.05, 0.05);
  D.k2 = Uniform(rng, -0.02, 0.02);
  D.k3 = Uniform(rng, -0.01, 0.01);
  D.k4 = Uniform(rng, -0.005, 0.005);
  return D;
}

// The point at angle of incidence theta, azimuth phi, distance rho from the camera centre.
Eigen::Vector3d PointAt(double theta, double phi, double rho) {
  return rho * Eigen::Vector3d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                               std::cos(theta));
}

struct EquidistantSample {
  EquidistantDistortion D;
  Eigen::Vector3d p_c;
  std::string what;
};

// Curated cases first: the optical axis, both sides of the series branch at theta = 1e-6, the
// edge of the 180 deg field of view, the edge of a lens whose theta_d stops increasing, zero
// coefficients; then random lenses and points up to the valid angle.
EquidistantSample SampleEquidistant(Rng& rng, int i) {
  EquidistantSample s;
  s.D = RandomEquidistant(rng);
  const double phi = Uniform(rng, -M_PI, M_PI);
  const double rho = Uniform(rng, 0.5, 20.0);
  s.p_c = PointAt(Uniform(rng, 0.0, 0.999) * EquidistantValidTheta(s.D), phi, rho);
  switch (i) {
    case 0:
      s.p_c = Eigen::Vector3d(0, 0, 3);
      s.what = "on the optical axis";
      break;
    case 1:
      s.p_c = Eigen::Vector3d(2e-9, -1e-9, 0.7);
      s.what = "near the optical axis";
      break;
    case 2:
      s.p_c = PointAt(0.999e-6, phi, rho);
      s.what = "theta just below the series branch";
      break;
    case 3:
      s.p_c = PointAt(1.001e-6, phi, rho);
      s.what = "theta just above the series branch";
      break;
    case 4:
      s.p_c = PointAt(EquidistantValidTheta(s.D) - 1e-5, phi, rho);  // pi/2 unless theta_d folds
      s.what = "edge of the valid field of view";
      break;
    case 5:
      s.D = EquidistantDistortion{-0.2, 0.0, 0.0, 0.0};  // theta_d' = 0 near 73.5 deg
      s.p_c = PointAt(EquidistantValidTheta(s.D) - 1e-5, phi, rho);
      s.what = "edge of a folding lens's valid region";
      break;
    case 6:
      s.D = EquidistantDistortion{};
      s.what = "zero coefficients";
      break;
    default:
      break;
  }
  return s;
}

Eigen::VectorXd OrNan(const std::optional<Eigen::Vector2d>& v) {
  return v ? Eigen::VectorXd(*v) : Eigen::VectorXd::Constant(2, std::nan(""));
}

JacobianCheckStats CheckEquidistantProject(const JacobianCheckOptions& o) {
  JacobianCheckStats s;
  s.name = "camera.equidistant.Project";
  Rng rng(o.seed + 601);
  for (int i = 0; i < o.samples; ++i) {
    const EquidistantSample c = SampleEquidistant(rng, i);
    Eigen::Matrix<double, 2, 3> J;
    if (!EquidistantProject(c.D, c.p_c, &J)) {
      ++s.skipped;
      continue;
    }
    auto twin = [&](const auto& d) {
      using T = typename std::decay_t<decltype(d)>::Scalar;
      return EquidistantProjectT<T>(c.D, Eigen::Matrix<T, 3, 1>(c.p_c.cast<T>() + d));
    };
    const Eigen::Matrix<double, 2, 3> Jad = AutoDiffJacobian<3, 2>(twin, Eigen::Vector3d::Zero());
    const Eigen::MatrixXd Jnum = NumericJacobian(
        [&](const Eigen::VectorXd& d) {
          return OrNan(EquidistantProject(c.D, Eigen::Vector3d(c.p_c + d)));
        },
        Eigen::VectorXd::Zero(3));
    s.Add(J, Jad, Jnum, c.what);
  }
  return s;
}

// Camera::ProjectWithJacobian of a camera of the given model, on the same kind of points.
JacobianCheckStats CheckCameraProject(const JacobianCheckOptions& o, sensor::CameraModel model) {
  JacobianCheckStats s;
  const bool kb = model == sensor::CameraModel::kEquidistant;
  s.name = kb ? "camera.equidistant.CameraProject" : "camera.radtan.CameraProject";
  Rng rng(o.seed + (kb ? 602 : 603));
  for (int i = 0; i < o.samples; ++i) {
    sensor::Camera camera;
    camera.K = SampleIntrinsics(rng);
    camera.width = 752;
    camera.height = 480;
    camera.model = model;
    EquidistantSample c = SampleEquidistant(rng, i);
    camera.equidistant = c.D;
    if (!kb) {  // radtan: EuRoC-like coefficients, points within 60 deg (z > 0)
      camera.distortion.k1 = Uniform(rng, -0.35, 0.1);
      camera.distortion.k2 = Uniform(rng, -0.1, 0.1);
      camera.distortion.p1 = Uniform(rng, -2e-3, 2e-3);
      camera.distortion.p2 = Uniform(rng, -2e-3, 2e-3);
      camera.distortion.k3 = i == 6 ? 0.0 : Uniform(rng, -0.02, 0.02);
      if (i == 6) camera.distortion = RadTanDistortion{};
      if (i >= 4) c.p_c = PointAt(Uniform(rng, 0.0, M_PI / 3), Uniform(rng, -M_PI, M_PI), 5.0);
    }
    Eigen::Matrix<double, 2, 3> J;
    if (!camera.ProjectWithJacobian(c.p_c, &J)) {
      ++s.skipped;
      continue;
    }
    auto twin = [&](const auto& d) {
      using T = typename std::decay_t<decltype(d)>::Scalar;
      const Eigen::Matrix<T, 3, 1> p = c.p_c.cast<T>() + d;
      if (kb) return camera.K.ToPixel<T>(EquidistantProjectT<T>(camera.equidistant, p));
      return camera.K.ToPixel<T>(
          DistortT<T>(camera.distortion, Eigen::Matrix<T, 2, 1>(p(0) / p(2), p(1) / p(2))));
    };
    const Eigen::Matrix<double, 2, 3> Jad = AutoDiffJacobian<3, 2>(twin, Eigen::Vector3d::Zero());
    const Eigen::MatrixXd Jnum =
        NumericJacobian([&](const Eigen::VectorXd& d) { return OrNan(camera.Project(c.p_c + d)); },
                        Eigen::VectorXd::Zero(3));
    s.Add(J, Jad, Jnum, kb ? c.what : std::string("radtan ") + std::to_string(i));
  }
  return s;
}

}  // namespace

std::vector<NamedJacobianCheck> CameraJacobianChecks() {
  return {{"camera.equidistant.Project", CheckEquidistantProject},
          {"camera.equidistant.CameraProject",
           [](const JacobianCheckOptions& o) {
             return CheckCameraProject(o, sensor::CameraModel::kEquidistant);
           }},
          {"camera.radtan.CameraProject", [](const JacobianCheckOptions& o) {
             return CheckCameraProject(o, sensor::CameraModel::kRadialTangential);
           }}};
}

}  // namespace verify
}  // namespace plucker
