// Jacobian checks of geometry/so3.h and geometry/se3.h.
#include <sstream>

#include "plucker/geometry/se3.h"
#include "plucker/verify/checks.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace verify {

namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;
using Vector12 = Eigen::Matrix<double, 12, 1>;

Eigen::VectorXd Tangent(const SE3d& x, const SE3d& base) { return x.Minus(base); }

JacobianCheckStats CheckCompose(const JacobianCheckOptions& o) {
  JacobianCheckStats s;
  s.name = "se3.Compose";
  Rng rng(o.seed);
  for (int i = 0; i < o.samples; ++i) {
    const SE3d a = SamplePose(rng, i), b = SamplePose(rng, i + 2);
    Matrix6d Ja, Jb;
    const SE3d ab = Compose(a, b, &Ja, &Jb);
    auto twin = [&](const auto& d) {
      using T = typename std::decay_t<decltype(d)>::Scalar;
      const SE3<T> a_t = a.cast<T>().Plus(d.template head<6>());
      const SE3<T> b_t = b.cast<T>().Plus(d.template tail<6>());
      return Eigen::Matrix<T, 6, 1>((a_t * b_t).Minus(ab.cast<T>()));
    };
    const Eigen::Matrix<double, 6, 12> Jad = AutoDiffJacobian<12, 6>(twin, Vector12::Zero());
    const Eigen::MatrixXd Jnum = NumericJacobian(
        [&](const Eigen::VectorXd& d) {
          return Tangent(a.Plus(d.head<6>()) * b.Plus(d.tail<6>()), ab);
        },
        Eigen::VectorXd::Zero(12));
    Eigen::Matrix<double, 6, 12> J;
    J << Ja, Jb;
    s.Add(J, Jad, Jnum);
  }
  return s;
}

JacobianCheckStats CheckInverse(const JacobianCheckOptions& o) {
  JacobianCheckStats s;
  s.name = "se3.Inverse";
  Rng rng(o.seed + 1);
  for (int i = 0; i < o.samples; ++i) {
    const SE3d a = SamplePose(rng, i);
    Matrix6d J;
    const SE3d inv = Inverse(a, &J);
    auto twin = [&](const auto& d) {
      using T = typename std::decay_t<decltype(d)>::Scalar;
      return Eigen::Matrix<T, 6, 1>(a.cast<T>().Plus(d).Inverse().Minus(inv.cast<T>()));
    };
    const Matrix6d Jad = AutoDiffJacobian<6, 6>(twin, Vector6::Zero());
    const Eigen::MatrixXd Jnum =
        NumericJacobian([&](const Eigen::VectorXd& d) { return Tangent(a.Plus(d).Inverse(), inv); },
                        Eigen::VectorXd::Zero(6));
    s.Add(J, Jad, Jnum);
  }
  return s;
}

JacobianCheckStats CheckTransformPoint(const JacobianCheckOptions& o) {
  JacobianCheckStats s;
  s.name = "se3.TransformPoint";
  Rng rng(o.seed + 2);
  for (int i = 0; i < o.samples; ++i) {
    const SE3d a = SamplePose(rng, i);
    const Eigen::Vector3d p = i == 4 ? Eigen::Vector3d::Zero() : RandomVector(rng, 5.0);
    Eigen::Matrix<double, 3, 6> Jpose;
    Eigen::Matrix3d Jpoint;
    TransformPoint(a, p, &Jpose, &Jpoint);
    auto twin = [&](const auto& d) {
      using T = typename std::decay_t<decltype(d)>::Scalar;
      const Vector3<T> p_t = p.cast<T>() + d.template tail<3>();
      return Eigen::Matrix<T, 3, 1>(a.cast<T>().Plus(d.template head<6>()) * p_t);
    };
    const Eigen::Matrix<double, 3, 9> Jad =
        AutoDiffJacobian<9, 3>(twin, Eigen::Matrix<double, 9, 1>::Zero());
    const Eigen::MatrixXd Jnum = NumericJacobian(
        [&](const Eigen::VectorXd& d) {
          return Eigen::VectorXd(a.Plus(d.head<6>()) * (p + d.tail<3>()));
        },
        Eigen::VectorXd::Zero(9));
    Eigen::Matrix<double, 3, 9> J;
    J << Jpose, Jpoint;
    s.Add(J, Jad, Jnum);
  }
  return s;
}

// Rotation vectors: random, tiny, and near pi.
Eigen::Vector3d SampleRotationVector(Rng& rng, int i) {
  if (i == 0) return Eigen::Vector3d::Zero();
  if (i == 1) return RandomUnitVector(rng) * 1e-9;
  if (i == 2) return RandomUnitVector(rng) * (M_PI - 1e-6);
  return RandomUnitVector(rng) * Uniform(rng, 0.0, M_PI - 1e-3);
}

// Jr(w) = d Log(Exp(w)^-1 Exp(w + dw)) / d dw.
JacobianCheckStats CheckRightJacobian(const JacobianCheckOptions& o) {
  JacobianCheckStats s;
  s.name = "so3.RightJacobian";
  Rng rng(o.seed + 3);
  for (int i = 0; i < o.samples; ++i) {
    const Eigen::Vector3d w = SampleRotationVector(rng, i);
    auto twin = [&](const auto& d) {
      using T = typename std::decay_t<decltype(d)>::Scalar;
      const Eigen::Quaternion<T> q0 = ExpSO3<double>(w).cast<T>();
      return LogSO3<T>(q0.conjugate() * ExpSO3<T>(w.cast<T>() + d));
    };
    const Eigen::Matrix3d Jad = AutoDiffJacobian<3, 3>(twin, Eigen::Vector3d::Zero());
    const Eigen::MatrixXd Jnum = NumericJacobian(
        [&](const Eigen::VectorXd& d) {
          return Eigen::VectorXd(
              LogSO3<double>(ExpSO3<double>(w).conjugate() * ExpSO3<double>(w + d)));
        },
        Eigen::VectorXd::Zero(3));
    s.Add(RightJacobianSO3(w), Jad, Jnum);
  }
  return s;
}

// Jr^-1(w) = d Log(Exp(w) Exp(dw)) / d dw (away from pi, where Log is smooth).
JacobianCheckStats CheckRightJacobianInverse(const JacobianCheckOptions& o) {
  JacobianCheckStats s;
  s.name = "so3.RightJacobianInverse";
  Rng rng(o.seed + 4);
  for (int i = 0; i < o.samples; ++i) {
    const Eigen::Vector3d w = i < 2 ? SampleRotationVector(rng, i)
                                    : RandomUnitVector(rng) * Uniform(rng, 0.0, M_PI - 0.1);
    auto twin = [&](const auto& d) {
      using T = typename std::decay_t<decltype(d)>::Scalar;
      return LogSO3<T>(ExpSO3<double>(w).cast<T>() * ExpSO3<T>(d));
    };
    const Eigen::Matrix3d Jad = AutoDiffJacobian<3, 3>(twin, Eigen::Vector3d::Zero());
    const Eigen::MatrixXd Jnum = NumericJacobian(
        [&](const Eigen::VectorXd& d) {
          return Eigen::VectorXd(LogSO3<double>(ExpSO3<double>(w) * ExpSO3<double>(d)));
        },
        Eigen::VectorXd::Zero(3));
    s.Add(RightJacobianInverseSO3(w), Jad, Jnum);
  }
  return s;
}

}  // namespace

std::vector<NamedJacobianCheck> SE3JacobianChecks() {
  return {{"so3.RightJacobian", CheckRightJacobian},
          {"so3.RightJacobianInverse", CheckRightJacobianInverse},
          {"se3.Compose", CheckCompose},
          {"se3.Inverse", CheckInverse},
          {"se3.TransformPoint", CheckTransformPoint}};
}

}  // namespace verify
}  // namespace plucker
