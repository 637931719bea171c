// The parts of the plucker._plucker extension module (module.cc calls each once).
#pragma once

#include <pybind11/pybind11.h>

namespace plucker {
namespace python {

void RegisterGeometry(pybind11::module_& m);  // geometry.cc
void RegisterFactors(pybind11::module_& m);   // factors.cc
void RegisterIo(pybind11::module_& m);        // io.cc
void RegisterEval(pybind11::module_& m);      // eval.cc
void RegisterLidar(pybind11::module_& m);     // lidar.cc
void RegisterVio(pybind11::module_& m);       // vio.cc
void RegisterVo(pybind11::module_& m);        // vo.cc
void RegisterBag(pybind11::module_& m);       // bag.cc

}  // namespace python
}  // namespace plucker
