// plucker.geometry bindings: SO(3)/SE(3) charts, Plücker lines, the orthonormal representation,
// line projection and triangulation. Poses are 4x4 numpy arrays named T_a_b (p_a = T_a_b p_b).
#include <pybind11/stl.h>

#include "arrays.h"
#include "bindings.h"
#include "plucker/geometry/line_projection.h"
#include "plucker/geometry/line_triangulation.h"
#include "plucker/geometry/orthonormal_line.h"
#include "plucker/geometry/plucker_line.h"
#include "plucker/geometry/point_triangulation.h"
#include "plucker/geometry/se3.h"

namespace plucker {
namespace python {

namespace {

Line6d Line(const py::handle& obj, const char* name) {
  const Line6d L = Vec<6>(obj, name);
  if (!IsValidLine(L, 1e-6))
    throw py::value_error(std::string(name) +
                          ": not a Plücker line (needs |d| > 0 and n . d = 0 to 1e-6 relative)");
  return L;
}

std::vector<LineObservation> LineObservations(const py::handle& T_w_c, const py::handle& segments) {
  const std::vector<SE3d> poses = Poses(T_w_c, "T_w_c");
  const py::array s = py::array::ensure(segments);
  if (!s || s.ndim() != 2 || s.shape(0) != static_cast<py::ssize_t>(poses.size()) ||
      s.shape(1) != 4)
    throw py::value_error("segments: expected shape (" + std::to_string(poses.size()) +
                          ", 4) (x1 y1 x2 y2 per view)" + (s ? ", got " + ShapeText(s) : ""));
  const Eigen::MatrixXd m = SmallMatrix(s, "segments", static_cast<int>(poses.size()), 4);
  std::vector<LineObservation> obs(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    obs[i].T_w_c = poses[i];
    obs[i].start = m.row(static_cast<Eigen::Index>(i)).head<2>().transpose();
    obs[i].end = m.row(static_cast<Eigen::Index>(i)).tail<2>().transpose();
  }
  return obs;
}

py::dict LineResult(const LineTriangulationResult& r) {
  py::dict d;
  d["ok"] = r.ok();
  d["status"] = ToString(r.status);
  d["message"] = r.message;
  d["L_w"] = ToVector(r.L_w);
  d["start_w"] = ToVector(r.start_w);
  d["end_w"] = ToVector(r.end_w);
  d["sigma_ratio"] = r.sigma_ratio;
  d["min_parallax_rad"] = r.min_parallax_rad;
  d["max_parallax_rad"] = r.max_parallax_rad;
  d["rms_error_px"] = r.rms_error_px;
  d["max_error_px"] = r.max_error_px;
  d["refine_iterations"] = r.refine_iterations;
  return d;
}

void RegisterRotations(py::module_& m) {
  m.def(
      "so3_exp", [](const py::handle& w) { return ToArray(ExpSO3Matrix<double>(Vec<3>(w, "w"))); },
      py::arg("w"), "Rotation matrix Exp(w) of a rotation vector w (3,) in radians: (3, 3).");
  m.def(
      "so3_log",
      [](const py::handle& R) {
        const Eigen::Matrix3d m = Mat<3, 3>(R, "R");
        if ((m.transpose() * m - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 ||
            m.determinant() <= 0.0)
          throw py::value_error("R: not a rotation matrix");
        return ToVector(LogSO3(Eigen::Quaterniond(m)));
      },
      py::arg("R"), "Rotation vector w (3,) with Exp(w) = R, |w| <= pi.");
  m.def(
      "se3_exp", [](const py::handle& xi) { return PoseMatrix(SE3d::Retract(Vec<6>(xi, "xi"))); },
      py::arg("xi"),
      "The library's SE(3) chart (docs/conventions.md): xi = (w, t) (6,) -> 4x4 T with R = Exp(w)\n"
      "and translation t (rotation and translation decoupled, as PoseManifold's Plus).");
  m.def(
      "se3_log",
      [](const py::handle& T) {
        const SE3d pose = Pose(T, "T");
        Vector6d xi;
        xi << LogSO3(pose.rotation()), pose.translation();
        return ToVector(xi);
      },
      py::arg("T"), "Inverse of se3_exp: 4x4 T -> (w, t) (6,).");
  m.def(
      "se3_plus",
      [](const py::handle& T, const py::handle& delta) {
        return PoseMatrix(Pose(T, "T").Plus(Vec<6>(delta, "delta")));
      },
      py::arg("T"), py::arg("delta"),
      "T (+) delta = (R Exp(dtheta), t + dt), the PoseManifold step; delta = (dtheta, dt).");
  m.def(
      "se3_minus",
      [](const py::handle& T, const py::handle& T0) {
        return ToVector(Pose(T, "T").Minus(Pose(T0, "T0")));
      },
      py::arg("T"), py::arg("T0"), "delta (6,) with se3_plus(T0, delta) = T.");
  m.def(
      "compose",
      [](const py::handle& T_a_b, const py::handle& T_b_c) {
        Matrix6d J_ab, J_bc;
        const SE3d T = Compose(Pose(T_a_b, "T_a_b"), Pose(T_b_c, "T_b_c"), &J_ab, &J_bc);
        return py::make_tuple(PoseMatrix(T), ToArray(J_ab), ToArray(J_bc));
      },
      py::arg("T_a_b"), py::arg("T_b_c"),
      "(T_a_c, dT_a_c/dT_a_b, dT_a_c/dT_b_c): the Jacobians (6, 6) in the (dtheta, dt) tangent.");
  m.def(
      "transform_point",
      [](const py::handle& T_a_b, const py::handle& p_b) {
        Eigen::Matrix<double, 3, 6> J_pose;
        Eigen::Matrix3d J_p;
        const Eigen::Vector3d p =
            TransformPoint(Pose(T_a_b, "T_a_b"), Vec<3>(p_b, "p_b"), &J_pose, &J_p);
        return py::make_tuple(ToVector(p), ToArray(J_pose), ToArray(J_p));
      },
      py::arg("T_a_b"), py::arg("p_b"), "(p_a, dp_a/dT_a_b (3, 6), dp_a/dp_b (3, 3)).");
}

void RegisterLines(py::module_& m) {
  m.def(
      "line_from_points",
      [](const py::handle& p1, const py::handle& p2) {
        const Eigen::Vector3d a = Vec<3>(p1, "p1"), b = Vec<3>(p2, "p2");
        if (a == b) throw py::value_error("p1, p2: the same point defines no line");
        return ToVector(LineFromPoints<double>(a, b));
      },
      py::arg("p1"), py::arg("p2"), "Plücker line L = (n, d) = (p1 x p2, p2 - p1) (6,).");
  m.def(
      "transform_line",
      [](const py::handle& T_a_b, const py::handle& L_b) {
        Matrix6d J_T, J_L;
        const Line6d L = TransformLine(Pose(T_a_b, "T_a_b"), Line(L_b, "L_b"), &J_T, &J_L);
        return py::make_tuple(ToVector(L), ToArray(J_T), ToArray(J_L));
      },
      py::arg("T_a_b"), py::arg("L_b"),
      "(L_a, dL_a/dT_a_b (6, 6), dL_a/dL_b (6, 6)) with L_a = H(T_a_b) L_b.");
  m.def(
      "line_to_orthonormal",
      [](const py::handle& L) {
        const auto o = OrthonormalFromPlucker(Line(L, "L"));
        if (!o) throw py::value_error("L: has no orthonormal representation");
        Eigen::Matrix<double, 6, 1> p;
        o->ToParameters(p.data());
        return ToVector(p);
      },
      py::arg("L"), "Orthonormal parameters [qx, qy, qz, qw, w1, w2] (6,) of a Plücker line.");
  m.def(
      "line_from_orthonormal",
      [](const py::handle& p) {
        const Eigen::Matrix<double, 6, 1> v = Vec<6>(p, "p");
        if (v.head<4>().norm() == 0.0 || v.tail<2>().norm() == 0.0)
          throw py::value_error("p: the quaternion and W must be non-zero");
        Eigen::Matrix<double, 6, 4> J;
        const Line6d L = PluckerFromOrthonormal(OrthonormalLine::FromParameters(v.data()), &J);
        return py::make_tuple(ToVector(L), ToArray(J));
      },
      py::arg("p"),
      "(L (6,), dL/ddelta (6, 4)): Plücker line (unit norm) of orthonormal parameters.");
  m.def(
      "line_intrinsics", [](const py::handle& K) { return ToArray(LineIntrinsics(Intrinsics(K))); },
      py::arg("K"), "The line intrinsic matrix K_line (3, 3) of K = (fx, fy, cx, cy).");
  m.def(
      "project_line",
      [](const py::handle& K, const py::handle& L_c) {
        Eigen::Matrix<double, 3, 6> J;
        const Eigen::Vector3d l = ProjectLinePixels(Intrinsics(K), Line(L_c, "L_c"), &J);
        return py::make_tuple(ToVector(l), ToArray(J));
      },
      py::arg("K"), py::arg("L_c"),
      "(l (3,), dl/dL_c (3, 6)): image line l = K_line n_c in pixels of a camera-frame line.");
  m.def(
      "triangulate_line",
      [](const py::handle& K, const py::handle& T_w_c, const py::handle& segments, bool refine) {
        const PinholeIntrinsics k = Intrinsics(K);
        const std::vector<LineObservation> obs = LineObservations(T_w_c, segments);
        py::gil_scoped_release release;
        const LineTriangulationResult r =
            refine ? TriangulateLineRefined(k, obs) : TriangulateLine(k, obs);
        py::gil_scoped_acquire acquire;
        return LineResult(r);
      },
      py::arg("K"), py::arg("T_w_c"), py::arg("segments"), py::arg("refine") = true,
      "N-view line triangulation from camera poses T_w_c (N, 4, 4) and segments (N, 4) in ideal\n"
      "pixels; a dict with ok, status, message, L_w, start_w, end_w, errors and conditioning.");
  m.def(
      "triangulate_point",
      [](const py::handle& K, const py::handle& T_w_c, const py::handle& uv) {
        const PinholeIntrinsics k = Intrinsics(K);
        const std::vector<SE3d> poses = Poses(T_w_c, "T_w_c");
        const Eigen::MatrixXd m = SmallMatrix(uv, "uv", static_cast<int>(poses.size()), 2);
        std::vector<Eigen::Vector2d> pixels(poses.size());
        for (std::size_t i = 0; i < poses.size(); ++i)
          pixels[i] = m.row(static_cast<Eigen::Index>(i)).transpose();
        const PointTriangulationResult r = TriangulatePoint(k, poses, pixels);
        py::dict d;
        d["ok"] = r.ok();
        d["status"] = ToString(r.status);
        d["message"] = r.message;
        d["p_w"] = ToVector(r.p_w);
        d["max_parallax_rad"] = r.max_parallax_rad;
        d["initial_rms_px"] = r.initial_rms_px;
        d["final_rms_px"] = r.final_rms_px;
        d["iterations"] = r.iterations;
        return d;
      },
      py::arg("K"), py::arg("T_w_c"), py::arg("uv"),
      "N-view point triangulation (DLT + Gauss-Newton) from T_w_c (N, 4, 4) and pixels uv (N, 2).");
}

}  // namespace

void RegisterGeometry(py::module_& m) {
  RegisterRotations(m);
  RegisterLines(m);
}

}  // namespace python
}  // namespace plucker
