// One options table per command (`plucker lidar`, `vo`, `vio`): typed rows with a dotted key,
// type, unit, range and one-line doc, reading and writing one member of the command's config
// struct. From the table come the YAML reader (`--config FILE.yaml`), the command-line flags that
// set the same option (OptionsTable::Set: the flag overrides the file), the defaults file
// config/<command>_default.yaml and the documentation table (`plucker config <command>
// [--markdown]`); scripts/update_options.sh rewrites the generated files and
// app_options_table_test fails while one is stale.
//
// Errors name the file (or the flag) and the key: unknown key, a renamed key (with its new
// name, so that an old file is not silently ignored), wrong type, out of range, invalid YAML.
//
// To add an option: one row in the command's table (e.g. lidar_options_table.cc), then run
// scripts/update_options.sh.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace plucker {
namespace app {

// The valid values of a numeric option: finite, lo <= v (lo < v if lo_open) and v <= hi.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool Contains(double v) const {
    return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && v <= hi;
  }
  std::string Text() const;  // "[2, 1000]", ">= 0", "> 0", "any"
};
inline Range Between(double lo, double hi) { return {lo, hi, false}; }
inline Range AtLeast(double lo) { return {lo, std::numeric_limits<double>::infinity(), false}; }
inline Range Above(double lo) { return {lo, std::numeric_limits<double>::infinity(), true}; }
inline Range AnyValue() { return {}; }

// What two tables share for one option (the same key, unit, doc and range in both).
struct OptionSpec {
  const char* key;
  const char* unit;
  const char* doc;
  Range range;
};

template <typename Config>
struct OptionRow {
  std::string key;    // dotted YAML path, e.g. "features.min_range"
  std::string type;   // "number", "integer", "bool", "list", or the choices "huber | cauchy"
  std::string unit;   // "m", "deg", ... or empty
  std::string doc;    // one line
  std::string range;  // Range::Text(), or empty (bool, choices)
  std::function<std::string(const Config&)> get;  // the value as YAML text
  // Sets the value from a YAML node; throws std::invalid_argument("expected ...") or
  // ("value ... out of range ...").
  std::function<void(const YAML::Node&, Config*)> set;
};

namespace options_internal {

// Shortest text that reads back as the same double; integral values keep a ".0".
std::string FormatNumber(double v);
std::string FormatNumber(int v);
// The (key, value node) pairs of a YAML document, nested groups flattened to dotted keys.
// Throws std::runtime_error naming `name` for invalid YAML and a top level that is no mapping.
std::vector<std::pair<std::string, YAML::Node>> ParseEntries(const std::string& text,
                                                             const std::string& name);
std::string ReadFile(const std::string& path);  // throws std::runtime_error "path: cannot open"
std::string Escape(std::string text);           // '|' -> '\|' (Markdown cells)
std::string Comment(const std::string& type, const std::string& unit, const std::string& range,
                    const std::string& doc);

template <typename T>
struct Traits;
template <>
struct Traits<double> {
  static constexpr const char* kType = "number";
  static constexpr const char* kExpected = "a number";
};
template <>
struct Traits<int> {
  static constexpr const char* kType = "integer";
  static constexpr const char* kExpected = "an integer";
};

// A scalar of type T from a YAML node (std::invalid_argument "expected ..., got '...'").
template <typename T>
T Parse(const YAML::Node& n, const char* expected) {
  if (n.IsScalar()) {
    try {
      return n.as<T>();
    } catch (const YAML::Exception&) {
    }
  }
  throw std::invalid_argument(std::string("expected ") + expected + ", got '" +
                              (n.IsScalar() ? n.Scalar() : std::string("a non-scalar")) + "'");
}

}  // namespace options_internal

// Builds the rows of a table. `field` is a lambda returning a reference to the member of a
// (const) Config&, e.g. PLUCKER_OPTION_MEMBER(odometry.features.min_range).
template <typename Config>
class OptionRows {
 public:
  // A number or an integer (the member's type) within `range`; non-finite values are rejected.
  template <typename Field>
  void Value(const char* key, const char* unit, const char* doc, Range range, Field field) {
    using T = std::remove_reference_t<decltype(field(std::declval<Config&>()))>;
    static_assert(std::is_same<T, double>::value || std::is_same<T, int>::value, "number row");
    using options_internal::Traits;
    OptionRow<Config> o{key, Traits<T>::kType, unit, doc, range.Text(), nullptr, nullptr};
    o.get = [field](const Config& c) { return options_internal::FormatNumber(field(c)); };
    o.set = [field, range](const YAML::Node& n, Config* c) {
      const T v = options_internal::Parse<T>(n, Traits<T>::kExpected);
      if (!range.Contains(static_cast<double>(v)))
        throw std::invalid_argument("value " + n.Scalar() + " out of range " + range.Text());
      field(*c) = v;
    };
    rows_.push_back(std::move(o));
  }
  template <typename Field>
  void Value(const OptionSpec& s, Field field) {
    Value(s.key, s.unit, s.doc, s.range, field);
  }
  template <typename Field>
  void Bool(const char* key, const char* doc, Field field) {
    OptionRow<Config> o{key, "bool", "", doc, "", nullptr, nullptr};
    o.get = [field](const Config& c) { return std::string(field(c) ? "true" : "false"); };
    o.set = [field](const YAML::Node& n, Config* c) {
      field(*c) = options_internal::Parse<bool>(n, "true or false");
    };
    rows_.push_back(std::move(o));
  }
  // A bool computed from and written into other members: get(const Config&) -> bool,
  // set(Config*, bool).
  template <typename Get, typename Set>
  void BoolWith(const char* key, const char* doc, Get get, Set set) {
    OptionRow<Config> o{key, "bool", "", doc, "", nullptr, nullptr};
    o.get = [get](const Config& c) { return std::string(get(c) ? "true" : "false"); };
    o.set = [set](const YAML::Node& n, Config* c) {
      set(c, options_internal::Parse<bool>(n, "true or false"));
    };
    rows_.push_back(std::move(o));
  }
  // An enumeration, written by name.
  template <typename Field, typename Enum>
  void Choice(const char* key, const char* doc, Field field,
              std::vector<std::pair<std::string, Enum>> names) {
    std::string type;
    for (const auto& [name, value] : names) type += (type.empty() ? "" : " | ") + name;
    OptionRow<Config> o{key, type, "", doc, "", nullptr, nullptr};
    o.get = [field, names](const Config& c) {
      for (const auto& [name, value] : names)
        if (value == field(c)) return name;
      throw std::logic_error("options table: unnamed value of " + names.front().first);
    };
    o.set = [field, names, type](const YAML::Node& n, Config* c) {
      for (const auto& [name, value] : names) {
        if (n.IsScalar() && n.Scalar() == name) {
          field(*c) = value;
          return;
        }
      }
      throw std::invalid_argument("expected " + type + ", got '" +
                                  (n.IsScalar() ? n.Scalar() : std::string("a non-scalar")) + "'");
    };
    rows_.push_back(std::move(o));
  }
  // Anything else: the caller's get and set.
  void Custom(OptionRow<Config> row) { rows_.push_back(std::move(row)); }

  std::vector<OptionRow<Config>> Take() { return std::move(rows_); }

 private:
  std::vector<OptionRow<Config>> rows_;
};

#define PLUCKER_OPTION_MEMBER(member) \
  [](auto& c) -> auto& { return c.member; }

// What a table prints around its rows.
struct TableText {
  std::string command;  // "lidar": `plucker lidar`, config/lidar_default.yaml
  std::string source;   // "apps/plucker/lidar_options_table.cc"
  std::map<std::string, std::string> group_comments;
  std::map<std::string, std::string> renamed;  // old key -> new key
};

template <typename Config>
class OptionsTable {
 public:
  OptionsTable(TableText text, std::vector<OptionRow<Config>> rows)
      : text_(std::move(text)), rows_(std::move(rows)) {}

  const std::vector<OptionRow<Config>>& rows() const { return rows_; }
  const TableText& text() const { return text_; }
  const OptionRow<Config>* Find(const std::string& key) const {
    for (const OptionRow<Config>& r : rows_)
      if (r.key == key) return &r;
    return nullptr;
  }

  // A YAML file setting every option to its value in `config`, grouped, each with its type,
  // unit, range and doc in a comment; `note(key)` (if set) is appended to a row's comment.
  std::string Yaml(const Config& config,
                   const std::function<std::string(const std::string&)>& note = nullptr) const;
  // The Markdown table (key, type, default, range, unit, meaning) of the defaults; `note` as in
  // Yaml, appended to the default's cell.
  std::string Markdown(const Config& defaults,
                       const std::function<std::string(const std::string&)>& note = nullptr) const;

  // Applies a YAML document (nested groups or dotted keys) to *config; keys left out keep their
  // value. Throws std::runtime_error "NAME: key 'KEY': PROBLEM" (unknown, renamed, wrong type,
  // out of range) or "NAME: invalid YAML: ...".
  void Apply(const std::string& yaml, const std::string& name, Config* config) const {
    for (const auto& [key, node] : options_internal::ParseEntries(yaml, name))
      SetNode(key, node, name, config);
  }
  void Load(const std::string& path, Config* config) const {
    Apply(options_internal::ReadFile(path), path, config);
  }
  // One value given as text (a command-line flag named `name`), checked as in a file.
  void Set(const std::string& key, const std::string& value, const std::string& name,
           Config* config) const {
    SetNode(key, YAML::Node(value), name, config);
  }

 private:
  void SetNode(const std::string& key, const YAML::Node& node, const std::string& name,
               Config* config) const {
    const auto renamed = text_.renamed.find(key);
    if (renamed != text_.renamed.end()) {
      throw std::runtime_error(name + ": key '" + key + "' was renamed to '" + renamed->second +
                               "'");
    }
    const OptionRow<Config>* row = Find(key);
    if (row == nullptr) throw std::runtime_error(name + ": unknown key '" + key + "'");
    try {
      row->set(node, config);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(name + ": key '" + key + "': " + e.what());
    }
  }

  TableText text_;
  std::vector<OptionRow<Config>> rows_;
};

// The generated text, without the table's type: (key, type, unit, range, doc, value, note).
namespace options_internal {
struct PrintedRow {
  std::string key, type, unit, range, doc, value, note;
};
std::string WriteYaml(const TableText& text, const std::vector<PrintedRow>& rows);
std::string WriteMarkdown(const std::vector<PrintedRow>& rows);
}  // namespace options_internal

template <typename Config>
std::string OptionsTable<Config>::Yaml(
    const Config& config, const std::function<std::string(const std::string&)>& note) const {
  std::vector<options_internal::PrintedRow> printed;
  for (const OptionRow<Config>& r : rows_)
    printed.push_back(
        {r.key, r.type, r.unit, r.range, r.doc, r.get(config), note ? note(r.key) : std::string()});
  return options_internal::WriteYaml(text_, printed);
}

template <typename Config>
std::string OptionsTable<Config>::Markdown(
    const Config& defaults, const std::function<std::string(const std::string&)>& note) const {
  std::vector<options_internal::PrintedRow> printed;
  for (const OptionRow<Config>& r : rows_)
    printed.push_back({r.key, r.type, r.unit, r.range, r.doc, r.get(defaults),
                       note ? note(r.key) : std::string()});
  return options_internal::WriteMarkdown(printed);
}

}  // namespace app
}  // namespace plucker
