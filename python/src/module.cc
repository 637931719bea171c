// The compiled part of the `plucker` Python package (python/plucker/__init__.py re-exports it).
#include "bindings.h"
#include "plucker/io/io_error.h"

PYBIND11_MODULE(_plucker, m) {
  m.doc() = "plucker: geometric features for SLAM (points, lines, planes) with analytic Jacobians";
  // Errors of the readers name the file and the problem; they are OSErrors in Python.
  auto& io_error = pybind11::register_exception<plucker::io::IoError>(m, "IoError", PyExc_OSError);
  io_error.attr("__doc__") =
      "A file could not be read or written: the message names the file and the problem.";
  plucker::python::RegisterGeometry(m);
  plucker::python::RegisterFactors(m);
  plucker::python::RegisterIo(m);
  plucker::python::RegisterEval(m);
  plucker::python::RegisterLidar(m);
  plucker::python::RegisterVio(m);
  plucker::python::RegisterVo(m);
  plucker::python::RegisterBag(m);
}
