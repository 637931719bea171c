// plucker.factors: the analytic Ceres cost functions (and their autodiff twins) evaluated on
// numpy parameter blocks. Pose blocks are [qx, qy, qz, qw, tx, ty, tz] (T_w_c, T_w_b, T_b_c,
// T_w_s), line blocks the orthonormal parameters [qx, qy, qz, qw, w1, w2], points (x, y, z).
#include <ceres/cost_function.h>
#include <pybind11/stl.h>

#include <memory>

#include "arrays.h"
#include "bindings.h"
#include "plucker/factors/anchored_line_factor.h"
#include "plucker/factors/lidar_factors.h"
#include "plucker/factors/line_manifold.h"
#include "plucker/factors/line_reprojection_factor.h"
#include "plucker/factors/point_reprojection_factor.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/factors/time_offset_factor.h"

namespace plucker {
namespace python {

namespace {

struct CostFunction {
  std::shared_ptr<ceres::CostFunction> f;
  std::string name;
};

py::tuple Evaluate(const CostFunction& c, const py::args& blocks) {
  const std::vector<int32_t>& sizes = c.f->parameter_block_sizes();
  if (blocks.size() != sizes.size())
    throw py::value_error(c.name + ": expected " + std::to_string(sizes.size()) +
                          " parameter blocks, got " + std::to_string(blocks.size()));
  std::vector<Eigen::VectorXd> x(sizes.size());
  std::vector<const double*> params(sizes.size());
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    const std::string what = c.name + " block " + std::to_string(i);
    x[i] = SmallMatrix(blocks[i], what.c_str(), sizes[i], 0);
    params[i] = x[i].data();
  }
  const int m = c.f->num_residuals();
  Eigen::VectorXd r(m);
  std::vector<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(
      sizes.size());
  std::vector<double*> jac(sizes.size());
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    J[i].resize(m, sizes[i]);
    jac[i] = J[i].data();
  }
  if (!c.f->Evaluate(params.data(), r.data(), jac.data()))
    throw py::value_error(c.name + ": the factor refuses this configuration (guarded case)");
  py::list jacobians;
  for (const auto& j : J) jacobians.append(ToArray(j));
  return py::make_tuple(ToVector(r), jacobians);
}

CostFunction Wrap(ceres::CostFunction* f, const std::string& name, bool autodiff) {
  return {std::shared_ptr<ceres::CostFunction>(f), name + (autodiff ? " (autodiff)" : "")};
}

Eigen::Matrix2d SqrtInformation(const py::object& obj) {
  return obj.is_none() ? Eigen::Matrix2d::Identity() : Mat<2, 2>(obj, "sqrt_information");
}

template <typename F>
void RegisterPointFactor(py::module_& m, const char* name, const char* doc) {
  m.def(
      name,
      [name](const py::handle& K, const py::handle& uv, const py::object& sqrt_information,
             bool autodiff) {
        const PinholeIntrinsics k = Intrinsics(K);
        const Eigen::Vector2d p = Vec<2>(uv, "uv");
        const Eigen::Matrix2d S = SqrtInformation(sqrt_information);
        return Wrap(autodiff ? F::CreateAutoDiff(k, p, S) : F::Create(k, p, S), name, autodiff);
      },
      py::arg("K"), py::arg("uv"), py::arg("sqrt_information") = py::none(),
      py::arg("autodiff") = false, doc);
}

template <typename F>
void RegisterLineFactor(py::module_& m, const char* name, const char* doc) {
  m.def(
      name,
      [name](const py::handle& K, const py::handle& s, const py::handle& e,
             const py::object& sqrt_information, bool autodiff) {
        const PinholeIntrinsics k = Intrinsics(K);
        const Eigen::Vector2d a = Vec<2>(s, "s_px"), b = Vec<2>(e, "e_px");
        const Eigen::Matrix2d S = SqrtInformation(sqrt_information);
        return Wrap(autodiff ? F::CreateAutoDiff(k, a, b, S) : F::Create(k, a, b, S), name,
                    autodiff);
      },
      py::arg("K"), py::arg("s_px"), py::arg("e_px"), py::arg("sqrt_information") = py::none(),
      py::arg("autodiff") = false, doc);
}

LineAnchor AnchorArg(const py::handle& c_w, double scale) {
  if (!(scale > 0.0) || !std::isfinite(scale))
    throw py::value_error("scale: must be positive and finite");
  LineAnchor anchor;
  anchor.c_w = Vec<3>(c_w, "c_w");
  anchor.scale = scale;
  return anchor;
}

template <typename F>
void RegisterAnchoredFactor(py::module_& m, const char* name, const char* doc) {
  m.def(
      name,
      [name](const py::handle& K, const py::handle& s, const py::handle& e, const py::handle& c_w,
             double scale, const py::object& sqrt_information, bool autodiff) {
        const PinholeIntrinsics k = Intrinsics(K);
        const Eigen::Vector2d a = Vec<2>(s, "s_px"), b = Vec<2>(e, "e_px");
        const Eigen::Matrix2d S = SqrtInformation(sqrt_information);
        const LineAnchor anchor = AnchorArg(c_w, scale);
        return Wrap(
            autodiff ? F::CreateAutoDiff(k, a, b, S, anchor) : F::Create(k, a, b, S, anchor), name,
            autodiff);
      },
      py::arg("K"), py::arg("s_px"), py::arg("e_px"), py::arg("c_w"), py::arg("scale"),
      py::arg("sqrt_information") = py::none(), py::arg("autodiff") = false, doc);
}

template <typename F>
void RegisterLidarFactor(py::module_& m, const char* name, const char* a_name, const char* b_name,
                         const char* doc) {
  m.def(
      name,
      [name, a_name, b_name](const py::handle& p_s, const py::handle& a, const py::handle& b,
                             double sigma, bool autodiff) {
        const Eigen::Vector3d p = Vec<3>(p_s, "p_s"), u = Vec<3>(a, a_name), v = Vec<3>(b, b_name);
        if (!(sigma > 0.0) || !std::isfinite(sigma))
          throw py::value_error("sigma: must be positive and finite");
        return Wrap(autodiff ? F::CreateAutoDiff(p, u, v, sigma) : F::Create(p, u, v, sigma), name,
                    autodiff);
      },
      py::arg("p_s"), py::arg(a_name), py::arg(b_name), py::arg("sigma") = 1.0,
      py::arg("autodiff") = false, doc);
}

// The camera-IMU time-offset factors (factors/time_offset_factor.h): a td block (1,) before the
// landmark, the features' image velocities (px/s) given.
void RegisterTimeOffsetFactors(py::module_& m) {
  using PointTd = PointReprojectionFactorVITimeOffset;
  using LineTd = AnchoredLineFactorVITimeOffset;
  m.def(
      "point_reprojection_vi_time_offset",
      [](const py::handle& K, const py::handle& uv, const py::handle& uv_velocity,
         const py::object& sqrt_information, bool autodiff) {
        const PinholeIntrinsics k = Intrinsics(K);
        const Eigen::Vector2d p = Vec<2>(uv, "uv"), v = Vec<2>(uv_velocity, "uv_velocity");
        const Eigen::Matrix2d S = SqrtInformation(sqrt_information);
        return Wrap(autodiff ? PointTd::CreateAutoDiff(k, p, v, S) : PointTd::Create(k, p, v, S),
                    "point_reprojection_vi_time_offset", autodiff);
      },
      py::arg("K"), py::arg("uv"), py::arg("uv_velocity"), py::arg("sqrt_information") = py::none(),
      py::arg("autodiff") = false,
      "Blocks (T_w_b, T_b_c, td (1,), p_w): point_reprojection_vi with the feature at uv - td v\n"
      "(Kalibr's t_imu = t_cam + td; uv_velocity: the track's image velocity, px/s).");
  m.def(
      "anchored_line_vi_time_offset",
      [](const py::handle& K, const py::handle& s, const py::handle& e, const py::handle& v_s,
         const py::handle& v_e, const py::handle& c_w, double scale,
         const py::object& sqrt_information, bool autodiff) {
        const PinholeIntrinsics k = Intrinsics(K);
        const Eigen::Vector2d a = Vec<2>(s, "s_px"), b = Vec<2>(e, "e_px");
        const Eigen::Vector2d va = Vec<2>(v_s, "s_velocity"), vb = Vec<2>(v_e, "e_velocity");
        const Eigen::Matrix2d S = SqrtInformation(sqrt_information);
        const LineAnchor anchor = AnchorArg(c_w, scale);
        return Wrap(autodiff ? LineTd::CreateAutoDiff(k, a, b, va, vb, S, anchor)
                             : LineTd::Create(k, a, b, va, vb, S, anchor),
                    "anchored_line_vi_time_offset", autodiff);
      },
      py::arg("K"), py::arg("s_px"), py::arg("e_px"), py::arg("s_velocity"), py::arg("e_velocity"),
      py::arg("c_w"), py::arg("scale"), py::arg("sqrt_information") = py::none(),
      py::arg("autodiff") = false,
      "Blocks (T_w_b, T_b_c, td (1,), anchored line): anchored_line_vi with the endpoints moved\n"
      "by -td times their image velocities (px/s).");
}

template <typename M>
void RegisterManifold(py::module_& m, const char* prefix, int ambient, int tangent) {
  const std::string plus = std::string(prefix) + "_plus", jac = plus + "_jacobian";
  m.def(
      plus.c_str(),
      [ambient, tangent](const py::handle& x, const py::handle& delta) {
        const Eigen::VectorXd a = SmallMatrix(x, "x", ambient, 0);
        const Eigen::VectorXd d = SmallMatrix(delta, "delta", tangent, 0);
        Eigen::VectorXd out(ambient);
        if (!M().Plus(a.data(), d.data(), out.data()))
          throw py::value_error("x: not a usable block");
        return ToVector(out);
      },
      py::arg("x"), py::arg("delta"), "The manifold's Plus(x, delta) as the solver applies it.");
  m.def(
      jac.c_str(),
      [ambient, tangent](const py::handle& x) {
        const Eigen::VectorXd a = SmallMatrix(x, "x", ambient, 0);
        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> J(ambient, tangent);
        if (!M().PlusJacobian(a.data(), J.data())) throw py::value_error("x: not a usable block");
        return ToArray(J);
      },
      py::arg("x"), "d Plus(x, delta) / d delta at delta = 0 (ambient x tangent).");
}

}  // namespace

void RegisterFactors(py::module_& parent) {
  py::module_ m = parent.def_submodule("factors", "Analytic factors and their autodiff twins");
  py::class_<CostFunction>(m, "CostFunction",
                           "A Ceres cost function; evaluate(*blocks) -> (residual, [jacobians]).")
      .def("evaluate", &Evaluate,
           "Residual (m,) and the row-major ambient Jacobians (m, block size), one per block.")
      .def_property_readonly("num_residuals",
                             [](const CostFunction& c) { return c.f->num_residuals(); })
      .def_property_readonly("parameter_block_sizes",
                             [](const CostFunction& c) {
                               const auto& s = c.f->parameter_block_sizes();
                               return std::vector<int>(s.begin(), s.end());
                             })
      .def_property_readonly("name", [](const CostFunction& c) { return c.name; })
      .def("__repr__",
           [](const CostFunction& c) { return "<plucker.factors.CostFunction " + c.name + ">"; });
  RegisterPointFactor<PointReprojectionFactor>(
      m, "point_reprojection",
      "Blocks (T_w_c, p_w): pixel reprojection error (2,) of a world point.");
  RegisterPointFactor<PointReprojectionFactorVI>(
      m, "point_reprojection_vi",
      "Blocks (T_w_b, T_b_c, p_w): the same through body and extrinsic.");
  RegisterLineFactor<LineReprojectionFactor>(
      m, "line_reprojection",
      "Blocks (T_w_c, line): endpoint-to-line distances (2,) in pixels of an observed segment.");
  RegisterLineFactor<LineReprojectionFactorVI>(
      m, "line_reprojection_vi", "Blocks (T_w_b, T_b_c, line): the same through the extrinsic.");
  RegisterAnchoredFactor<AnchoredLineFactor>(
      m, "anchored_line",
      "Blocks (T_w_c, anchored line): the line in the anchor's frame (c_w, scale).");
  RegisterAnchoredFactor<AnchoredLineFactorVI>(m, "anchored_line_vi",
                                               "Blocks (T_w_b, T_b_c, anchored line).");
  RegisterLidarFactor<PointToPlaneFactor>(m, "point_to_plane", "m_w", "q_w",
                                          "Block (T_w_s): signed distance (1,) of the scan point "
                                          "p_s from the plane (normal m_w through q_w) / sigma.");
  RegisterLidarFactor<PointToEdgeFactor>(m, "point_to_edge", "a_w", "b_w",
                                         "Block (T_w_s): offset (3,) of the scan point p_s from "
                                         "the line through a_w and b_w / sigma.");
  RegisterTimeOffsetFactors(m);
  RegisterManifold<PoseManifold>(m, "pose", 7, 6);
  RegisterManifold<LineManifold>(m, "line", 6, 4);
}

}  // namespace python
}  // namespace plucker
