#include "options.h"

#include <yaml-cpp/yaml.h>

#include <charconv>

namespace plucker {
namespace python {

std::string ScalarText(const py::handle& v, const std::string& key, const char* who) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(v)) return std::string(py::str(v));
  if (py::isinstance<py::float_>(v)) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof(buf), v.cast<double>());
    return std::string(buf, r.ptr);
  }
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  throw py::type_error(std::string(who) + ": option '" + key +
                       "': expected a bool, number or string, got " +
                       std::string(py::str(v.get_type().attr("__name__"))));
}

namespace {

YAML::Node ValueNode(const py::handle& value, const std::string& key, const char* who) {
  if (py::isinstance<py::dict>(value)) {
    YAML::Node map(YAML::NodeType::Map);
    for (const auto& kv : value.cast<py::dict>()) {
      const std::string sub = std::string(py::str(kv.first));
      map[sub] = ValueNode(kv.second, key + "." + sub, who);
    }
    return map;
  }
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    YAML::Node seq(YAML::NodeType::Sequence);
    for (const auto& item : value) seq.push_back(YAML::Node(ScalarText(item, key, who)));
    return seq;
  }
  return YAML::Node(ScalarText(value, key, who));
}

}  // namespace

std::string OptionsYaml(const py::kwargs& options, const char* who) {
  YAML::Node root(YAML::NodeType::Map);
  for (const auto& kv : options) {
    const std::string key = std::string(py::str(kv.first));
    root[key] = ValueNode(kv.second, key, who);
  }
  return YAML::Dump(root);
}

}  // namespace python
}  // namespace plucker
