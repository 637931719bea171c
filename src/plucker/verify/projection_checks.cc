// Jacobian checks of geometry/point_projection.h and geometry/distortion.h.
#include <sstream>

#include "plucker/geometry/distortion.h"
#include "plucker/geometry/point_projection.h"
#include "plucker/verify/checks.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace verify {

namespace {

using Vector9 = Eigen::Matrix<double, 9, 1>;

PinholeIntrinsics RandomIntrinsics(Rng& rng) {
  PinholeIntrinsics K;
  K.fx = Uniform(rng, 200.0, 1500.0);
  K.fy = K.fx * Uniform(rng, 0.9, 1.1);
  K.cx = Uniform(rng, 100.0, 800.0);
  K.cy = Uniform(rng, 100.0, 500.0);
  return K;
}

// A camera-frame point and its projection settings; curated hard cases first.
struct ProjectionSample {
  SE3d T_w_c;
  Eigen::Vector3d p_c;
  double min_depth = 1e-6;
  std::string what;
};

ProjectionSample SampleProjection(Rng& rng, int i) {
  ProjectionSample s;
  s.T_w_c = RandomPose(rng, 5.0);
  const double z = Uniform(rng, 0.3, 30.0);
  s.p_c = Eigen::Vector3d(Uniform(rng, -1.0, 1.0) * z, Uniform(rng, -0.8, 0.8) * z, z);
  switch (i) {
    case 0:  // on the principal axis, identity pose
      s.T_w_c = SE3d();
      s.p_c = Eigen::Vector3d(0, 0, 4);
      s.what = "on the principal axis";
      break;
    case 1:  // just off the principal axis
      s.p_c = Eigen::Vector3d(1e-9, -2e-9, 7);
      s.what = "near the principal axis";
      break;
    case 2:  // camera rotation of exactly pi
      s.T_w_c = SE3d(RotationNearPi(rng, 0.0), RandomVector(rng, 3.0));
      s.what = "rotation pi";
      break;
    case 3:
      s.T_w_c = SE3d(RotationNearPi(rng, 1e-7), RandomVector(rng, 3.0));
      s.what = "rotation near pi";
      break;
    case 4:  // 1e-4 above a min depth of 0.5 (the central-difference step is 1e-6)
      s.min_depth = 0.5;
      s.p_c = Eigen::Vector3d(0.2, -0.1, 0.5 + 1e-4);
      s.what = "just above min depth";
      break;
    case 5:  // very close to the camera with the default min depth
      s.p_c = Eigen::Vector3d(0.004, 0.003, 0.01);
      s.what = "1 cm in front of the camera";
      break;
    case 6:  // far, wide angle
      s.p_c = Eigen::Vector3d(300, -200, 100);
      s.what = "far, wide angle";
      break;
    default:
      break;
  }
  return s;
}

JacobianCheckStats CheckProjectPoint(const JacobianCheckOptions& o) {
  JacobianCheckStats s;
  s.name = "projection.ProjectPoint";
  Rng rng(o.seed + 101);
  for (int i = 0; i < o.samples; ++i) {
    const PinholeIntrinsics K = RandomIntrinsics(rng);
    const ProjectionSample c = SampleProjection(rng, i);
    const Eigen::Vector3d p_w = c.T_w_c * c.p_c;
    Eigen::Matrix<double, 2, 6> J_pose;
    Eigen::Matrix<double, 2, 3> J_point;
    if (!ProjectPoint(K, c.T_w_c, p_w, &J_pose, &J_point, c.min_depth)) {
      ++s.skipped;  // cannot happen for the samples above; counted, never silently passed
      continue;
    }
    auto twin = [&](const auto& d) {
      using T = typename std::decay_t<decltype(d)>::Scalar;
      const SE3<T> T_t = c.T_w_c.cast<T>().Plus(d.template head<6>());
      const Eigen::Matrix<T, 3, 1> p_t = p_w.cast<T>() + d.template tail<3>();
      Eigen::Matrix<T, 2, 1> uv = Eigen::Matrix<T, 2, 1>::Constant(T(std::nan("")));
      ProjectPointT<T>(K, T_t, p_t, &uv, c.min_depth);
      return uv;
    };
    const Eigen::Matrix<double, 2, 9> Jad = AutoDiffJacobian<9, 2>(twin, Vector9::Zero());
    const Eigen::MatrixXd Jnum = NumericJacobian(
        [&](const Eigen::VectorXd& d) {
          const auto uv = ProjectPoint(K, c.T_w_c.Plus(d.head<6>()), p_w + d.tail<3>(), nullptr,
                                       nullptr, c.min_depth);
          return uv ? Eigen::VectorXd(*uv) : Eigen::VectorXd::Constant(2, std::nan(""));
        },
        Eigen::VectorXd::Zero(9));
    Eigen::Matrix<double, 2, 9> J;
    J << J_pose, J_point;
    s.Add(J, Jad, Jnum, c.what);
  }
  return s;
}

JacobianCheckStats CheckProjectCameraPoint(const JacobianCheckOptions& o) {
  JacobianCheckStats s;
  s.name = "projection.ProjectCameraPoint";
  Rng rng(o.seed + 102);
  for (int i = 0; i < o.samples; ++i) {
    const PinholeIntrinsics K = RandomIntrinsics(rng);
    const ProjectionSample c = SampleProjection(rng, i);
    Eigen::Matrix<double, 2, 3> J;
    if (!ProjectCameraPoint(K, c.p_c, &J, c.min_depth)) {
      ++s.skipped;
      continue;
    }
    auto twin = [&](const auto& d) {
      using T = typename std::decay_t<decltype(d)>::Scalar;
      Eigen::Matrix<T, 2, 1> uv = Eigen::Matrix<T, 2, 1>::Constant(T(std::nan("")));
      ProjectCameraPointT<T>(K, Eigen::Matrix<T, 3, 1>(c.p_c.cast<T>() + d), &uv, c.min_depth);
      return uv;
    };
    const Eigen::Matrix<double, 2, 3> Jad = AutoDiffJacobian<3, 2>(twin, Eigen::Vector3d::Zero());
    const Eigen::MatrixXd Jnum = NumericJacobian(
        [&](const Eigen::VectorXd& d) {
          const auto uv = ProjectCameraPoint(K, c.p_c + d, nullptr, c.min_depth);
          return uv ? Eigen::VectorXd(*uv) : Eigen::VectorXd::Constant(2, std::nan(""));
        },
        Eigen::VectorXd::Zero(3));
    s.Add(J, Jad, Jnum, c.what);
  }
  return s;
}

JacobianCheckStats CheckDistort(const JacobianCheckOptions& o) {
  JacobianCheckStats s;
  s.name = "distortion.Distort";
  Rng rng(o.seed + 103);
  RadTanDistortion kitti;
  kitti.k1 = -0.3745594;
  kitti.k2 = 0.2049385;
  kitti.p1 = 1.110145e-3;
  kitti.p2 = 1.379375e-3;
  kitti.k3 = -0.07084798;
  for (int i = 0; i < o.samples; ++i) {
    RadTanDistortion D = kitti;
    Eigen::Vector2d x(Uniform(rng, -1.0, 1.0), Uniform(rng, -0.8, 0.8));
    std::string what;
    if (i == 0) {
      x.setZero();
      what = "principal point";
    } else if (i == 1) {
      x = Eigen::Vector2d(0.9, -0.7);
      what = "image corner, KITTI";
    } else if (i == 2) {
      D = RadTanDistortion();
      what = "zero distortion";
    } else if (i >= 3) {
      D.k1 = Uniform(rng, -0.5, 0.5);
      D.k2 = Uniform(rng, -0.3, 0.3);
      D.p1 = Uniform(rng, -0.01, 0.01);
      D.p2 = Uniform(rng, -0.01, 0.01);
      D.k3 = Uniform(rng, -0.1, 0.1);
    }
    Eigen::Matrix2d J;
    Distort(D, x, &J);
    auto twin = [&](const auto& d) {
      using T = typename std::decay_t<decltype(d)>::Scalar;
      return DistortT<T>(D, Eigen::Matrix<T, 2, 1>(x.cast<T>() + d));
    };
    const Eigen::Matrix2d Jad = AutoDiffJacobian<2, 2>(twin, Eigen::Vector2d::Zero());
    const Eigen::MatrixXd Jnum = NumericJacobian(
        [&](const Eigen::VectorXd& d) {
          return Eigen::VectorXd(Distort(D, Eigen::Vector2d(x + d)));
        },
        Eigen::VectorXd::Zero(2));
    s.Add(J, Jad, Jnum, what);
  }
  return s;
}

}  // namespace

std::vector<NamedJacobianCheck> ProjectionJacobianChecks() {
  return {{"projection.ProjectPoint", CheckProjectPoint},
          {"projection.ProjectCameraPoint", CheckProjectCameraPoint},
          {"distortion.Distort", CheckDistort}};
}

}  // namespace verify
}  // namespace plucker
