// Python keyword options as the YAML text the command line's option tables parse (the same keys,
// types, ranges and messages as `plucker config ...` and --config FILE.yaml).
#pragma once

#include <pybind11/pybind11.h>

#include <string>

namespace plucker {
namespace python {

namespace py = pybind11;

// A Python scalar (bool, int, float, str) as YAML text (numbers in the shortest exact form);
// TypeError naming `who` and the key for anything else.
std::string ScalarText(const py::handle& v, const std::string& key, const char* who);

// The options as a YAML mapping: dotted keys as given, dicts as groups, lists/tuples as
// sequences of scalars.
std::string OptionsYaml(const py::kwargs& options, const char* who);

}  // namespace python
}  // namespace plucker
