// _plucker_verify: the C++ Jacobian check registry (`plucker check-jacobians`) from Python, for
// the tests only (built in the build tree, never installed: verify is test scaffolding).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "plucker/verify/jacobian_check.h"

namespace py = pybind11;

PYBIND11_MODULE(_plucker_verify, m) {
  m.doc() = "The C++ Jacobian check registry (tests only)";
  m.def("check_names", []() {
    std::vector<std::string> names;
    for (const auto& c : plucker::verify::AllJacobianChecks()) names.push_back(c.name);
    return names;
  });
  m.def(
      "run_check",
      [](const std::string& name, int samples, std::uint64_t seed, bool record) {
        for (const auto& c : plucker::verify::AllJacobianChecks()) {
          if (c.name != name) continue;
          plucker::verify::JacobianCheckOptions o;
          o.samples = samples;
          o.seed = seed;
          std::vector<plucker::verify::FactorSampleRecord> records;
          if (record)
            o.factor_sample_observer = [&](const plucker::verify::FactorSampleRecord& r) {
              records.push_back(r);
            };
          plucker::verify::JacobianCheckStats s;
          {
            py::gil_scoped_release release;
            s = c.run(o);
          }
          py::dict d;
          py::list recs;
          for (const plucker::verify::FactorSampleRecord& r : records) {
            py::dict e, inputs;
            for (const auto& [key, value] : r.inputs) inputs[key.c_str()] = value;
            e["what"] = r.what;
            e["inputs"] = inputs;
            e["blocks"] = r.x;
            e["evaluated"] = r.evaluated;
            e["residual"] = r.residual;
            e["jacobians"] = r.jacobians;
            recs.append(e);
          }
          d["records"] = recs;
          d["samples"] = s.samples;
          d["skipped"] = s.skipped;
          d["worst_error_vs_autodiff"] = s.worst_autodiff;
          d["worst_error_vs_numeric"] = s.worst_numeric;
          d["autodiff_tolerance"] = s.autodiff_tolerance;
          d["numeric_tolerance"] = s.numeric_tolerance;
          d["failures"] = s.failures;
          d["passed"] = s.passed();
          return d;
        }
        throw py::value_error("no Jacobian check named '" + name + "'");
      },
      py::arg("name"), py::arg("samples") = 100, py::arg("seed") = 42, py::arg("record") = false);
}
