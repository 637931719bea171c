// Jacobian checks of geometry/plucker_line.h, geometry/orthonormal_line.h and
// geometry/line_projection.h (docs/math/lines.md). Each check compares the analytic Jacobian with
// the autodiff twin (templated value functions run with ceres::Jet) and with central differences
// on the manifold; the first samples are curated hard cases.
#include <cmath>
#include <limits>
#include <sstream>

#include "plucker/geometry/line_projection.h"
#include "plucker/geometry/orthonormal_line.h"
#include "plucker/geometry/plucker_line.h"
#include "plucker/verify/checks.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace verify {

namespace {

using Vector12 = Eigen::Matrix<double, 12, 1>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

// Lines: through the origin, u1 parallel to z (n = (0,0,1), d = (1,0,0)), far away, random.
Line6d SampleLine(Rng& rng, int i) {
  switch (i) {
    case 0:
      return LineFromPoints<double>(Eigen::Vector3d::Zero(), RandomVector(rng));
    case 1:
      return (Line6d() << 0, 0, 1, 1, 0, 0).finished();
    case 2: {
      const Eigen::Vector3d p = RandomUnitVector(rng) * 1e3;
      return LineFromPoints<double>(p, p + RandomVector(rng));
    }
    default:
      return LineFromPoints<double>(RandomVector(rng, 3.0), RandomVector(rng, 3.0));
  }
}

// L_a = H(T_a_b) L_b with Jacobians w.r.t. the pose tangent and L_b.
JacobianCheckStats CheckTransformLine(const JacobianCheckOptions& o) {
  JacobianCheckStats s;
  s.name = "line.TransformLine";
  Rng rng(o.seed + 100);
  for (int i = 0; i < o.samples; ++i) {
    const SE3d T = SamplePose(rng, i < 12 ? i / 3 : i);
    const Line6d L = SampleLine(rng, i < 12 ? i % 3 : i);
    Matrix6 J_pose, J_line;
    TransformLine(T, L, &J_pose, &J_line);
    auto twin = [&](const auto& d) {
      using T_ = typename std::decay_t<decltype(d)>::Scalar;
      const Line6<T_> L_t = L.cast<T_>() + d.template tail<6>();
      return TransformLine<T_>(T.cast<T_>().Plus(d.template head<6>()), L_t);
    };
    const Eigen::Matrix<double, 6, 12> J_ad = AutoDiffJacobian<12, 6>(twin, Vector12::Zero());
    const Eigen::MatrixXd J_num = NumericJacobian(
        [&](const Eigen::VectorXd& d) {
          return Eigen::VectorXd(TransformLine(T.Plus(d.head<6>()), Line6d(L + d.tail<6>())));
        },
        Eigen::VectorXd::Zero(12));
    Eigen::Matrix<double, 6, 12> J;
    J << J_pose, J_line;
    s.Add(J, J_ad, J_num);
  }
  return s;
}

// L_c = TransformLine(T_c_w, L_w) with the Jacobian w.r.t. the tangent of the held T_w_c.
JacobianCheckStats CheckTransformLineInversePose(const JacobianCheckOptions& o) {
  JacobianCheckStats s;
  s.name = "line.TransformLine.inverse_pose";
  Rng rng(o.seed + 101);
  for (int i = 0; i < o.samples; ++i) {
    const SE3d T_w_c = SamplePose(rng, i < 12 ? i / 3 : i);
    const Line6d L_w = SampleLine(rng, i < 12 ? i % 3 : i);
    Matrix6 J_line, J_pose;
    TransformLine(T_w_c.Inverse(), L_w, nullptr, &J_line, &J_pose);
    auto twin = [&](const auto& d) {
      using T_ = typename std::decay_t<decltype(d)>::Scalar;
      const Line6<T_> L_t = L_w.cast<T_>() + d.template tail<6>();
      return TransformLine<T_>(T_w_c.cast<T_>().Plus(d.template head<6>()).Inverse(), L_t);
    };
    const Eigen::Matrix<double, 6, 12> J_ad = AutoDiffJacobian<12, 6>(twin, Vector12::Zero());
    const Eigen::MatrixXd J_num = NumericJacobian(
        [&](const Eigen::VectorXd& d) {
          return Eigen::VectorXd(
              TransformLine(T_w_c.Plus(d.head<6>()).Inverse(), Line6d(L_w + d.tail<6>())));
        },
        Eigen::VectorXd::Zero(12));
    Eigen::Matrix<double, 6, 12> J;
    J << J_pose, J_line;
    s.Add(J, J_ad, J_num);
  }
  return s;
}

// Orthonormal lines: u1 // z, through the origin (phi = pi/2), phi near 0 (a line 1e9 from the
// origin), phi near pi/2, U near pi, random.
OrthonormalLine SampleOrthonormal(Rng& rng, int i) {
  OrthonormalLine line;
  auto random_w = [&] {
    const double phi = Uniform(rng, -M_PI, M_PI);
    return Eigen::Vector2d(std::cos(phi), std::sin(phi));
  };
  switch (i) {
    case 0:
      line = *OrthonormalFromPlucker((Line6d() << 0, 0, 1, 1, 0, 0).finished());
      break;
    case 1:
      line = *OrthonormalFromPlucker(
          LineFromPoints<double>(Eigen::Vector3d::Zero(), RandomUnitVector(rng)));
      break;
    case 2:
      line.U = RandomRotation(rng);
      line.W = Eigen::Vector2d(std::cos(1e-9), std::sin(1e-9));
      break;
    case 3:
      line.U = RandomRotation(rng);
      line.W = Eigen::Vector2d(std::cos(M_PI / 2 - 1e-9), std::sin(M_PI / 2 - 1e-9));
      break;
    case 4:
      line.U = RotationNearPi(rng, 0.0);
      line.W = random_w();
      break;
    case 5:
      line.U = RotationNearPi(rng, 1e-7);
      line.W = random_w();
      break;
    default:
      line.U = RandomRotation(rng);
      line.W = random_w();
  }
  return line;
}

// Value of L after the tangent update, written for Jets: U Exp(dtheta), W R(dphi).
template <typename T>
Line6<T> PluckerAfterPlus(const OrthonormalLine& line, const Eigen::Matrix<T, 4, 1>& d) {
  using std::cos;
  using std::sin;
  const Eigen::Quaternion<T> q = line.U.cast<T>() * ExpSO3<T>(d.template head<3>());
  const T c = cos(d(3)), sn = sin(d(3));
  const T p[6] = {q.x(),
                  q.y(),
                  q.z(),
                  q.w(),
                  T(line.W(0)) * c - T(line.W(1)) * sn,
                  T(line.W(0)) * sn + T(line.W(1)) * c};
  return PluckerFromOrthonormal<T>(p);
}

JacobianCheckStats CheckOrthonormalJacobian(const JacobianCheckOptions& o) {
  JacobianCheckStats s;
  s.name = "orthonormal.PluckerFromOrthonormal";
  Rng rng(o.seed + 102);
  for (int i = 0; i < o.samples; ++i) {
    const OrthonormalLine line = SampleOrthonormal(rng, i);
    Eigen::Matrix<double, 6, 4> J;
    PluckerFromOrthonormal(line, &J);
    auto twin = [&](const auto& d) {
      using T_ = typename std::decay_t<decltype(d)>::Scalar;
      return PluckerAfterPlus<T_>(line, d);
    };
    const Eigen::Matrix<double, 6, 4> J_ad = AutoDiffJacobian<4, 6>(twin, Eigen::Vector4d::Zero());
    const Eigen::MatrixXd J_num = NumericJacobian(
        [&](const Eigen::VectorXd& d) {
          return Eigen::VectorXd(PluckerFromOrthonormal(line.Plus(Eigen::Vector4d(d))));
        },
        Eigen::VectorXd::Zero(4));
    s.Add(J, J_ad, J_num);
  }
  return s;
}

// A camera-frame line seen by a typical camera: endpoints 2..10 m in front.
Line6d SampleCameraLine(Rng& rng) {
  auto point = [&] {
    return Eigen::Vector3d(Uniform(rng, -3, 3), Uniform(rng, -2, 2), Uniform(rng, 2, 10));
  };
  return LineFromPoints<double>(point(), point());
}

// Residual of an image segment w.r.t. the pixel line l.
JacobianCheckStats CheckEndpointLineResidual(const JacobianCheckOptions& o) {
  JacobianCheckStats s;
  s.name = "line_projection.EndpointLineResidual";
  Rng rng(o.seed + 103);
  for (int i = 0; s.samples < o.samples; ++i) {
    const PinholeIntrinsics K = SampleIntrinsics(rng);
    Line6d L_c = SampleCameraLine(rng);
    bool expect_guard = false;
    if (i == 0) {  // direction along the optical axis through the centre: projects to a point
      L_c = LineFromPoints<double>(Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, 5));
      expect_guard = true;
    } else if (i == 1) {  // in the principal plane z = 0: projects to the line at infinity
      L_c = LineFromPoints<double>(Eigen::Vector3d(1, 2, 0), Eigen::Vector3d(-3, 1, 0));
      expect_guard = true;
    } else if (i ==
               2) {  // parallel to the optical axis, off the centre: through the principal point
      L_c = LineFromPoints<double>(Eigen::Vector3d(0.5, -0.3, 1), Eigen::Vector3d(0.5, -0.3, 9));
    }
    const Eigen::Vector3d l = LineIntrinsics(K) * L_c.head<3>();
    const Eigen::Vector2d s_px(Uniform(rng, 0, 640), Uniform(rng, 0, 480));
    const Eigen::Vector2d e_px(Uniform(rng, 0, 640), Uniform(rng, 0, 480));
    Eigen::Matrix<double, 2, 3> J;
    const auto r = EndpointLineResidual(l, s_px, e_px, &J);
    if (expect_guard || !r) {
      if (expect_guard == r.has_value()) {  // guard missing, or refused a regular line: a failure
        const Eigen::MatrixXd bad =
            Eigen::MatrixXd::Constant(2, 3, std::numeric_limits<double>::quiet_NaN());
        s.Add(bad, bad, bad, expect_guard ? "guard expected" : "unexpected guard");
      } else {
        ++s.skipped;
      }
      continue;
    }
    auto twin = [&](const auto& x) {
      using T_ = typename std::decay_t<decltype(x)>::Scalar;
      Eigen::Matrix<T_, 2, 1> out = Eigen::Matrix<T_, 2, 1>::Zero();
      EndpointLineResidualT<T_>(x, s_px, e_px, &out);
      return out;
    };
    const Eigen::Matrix<double, 2, 3> J_ad = AutoDiffJacobian<3, 2>(twin, l);
    // Central differences with a step relative to |l| (pixel lines have |l| ~ f^2).
    const double h = 1e-7 * l.norm();
    Eigen::Matrix<double, 2, 3> J_num;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d lp = l, lm = l;
      lp(k) += h;
      lm(k) -= h;
      J_num.col(k) =
          (*EndpointLineResidual(lp, s_px, e_px) - *EndpointLineResidual(lm, s_px, e_px)) /
          (2.0 * h);
    }
    s.Add(J, J_ad, J_num);
  }
  return s;
}

}  // namespace

std::vector<NamedJacobianCheck> LineJacobianChecks() {
  return {{"line.TransformLine", CheckTransformLine},
          {"line.TransformLine.inverse_pose", CheckTransformLineInversePose},
          {"orthonormal.PluckerFromOrthonormal", CheckOrthonormalJacobian},
          {"line_projection.EndpointLineResidual", CheckEndpointLineResidual}};
}

}  // namespace verify
}  // namespace plucker
