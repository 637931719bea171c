#include "options_table.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace plucker {
namespace app {

std::string Range::Text() const {
  using options_internal::FormatNumber;
  // Integers print as integers ("[2, 1000]"), others in shortest form.
  auto text = [](double v) {
    if (v == std::floor(v) && std::fabs(v) < 1e9) return std::to_string(static_cast<long long>(v));
    return FormatNumber(v);
  };
  const bool low = std::isfinite(lo), high = std::isfinite(hi);
  if (low && high) return (lo_open ? "(" : "[") + text(lo) + ", " + text(hi) + "]";
  if (low) return (lo_open ? "> " : ">= ") + text(lo);
  if (high) return "<= " + text(hi);
  return "any";
}

namespace options_internal {

std::string FormatNumber(double v) {
  char buf[64];
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof(buf), "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 1e15)
    std::snprintf(buf, sizeof(buf), "%.1f", v);  // 100.0, not 1e+02
  return buf;
}

std::string FormatNumber(int v) { return std::to_string(v); }

namespace {

void Flatten(const YAML::Node& node, const std::string& prefix, const std::string& name,
             std::vector<std::pair<std::string, YAML::Node>>* out) {
  if (!node.IsMap()) {
    throw std::runtime_error(name + ": " + (prefix.empty() ? "top level" : "key '" + prefix + "'") +
                             " must be a mapping");
  }
  for (const auto& kv : node) {
    const std::string key = (prefix.empty() ? "" : prefix + ".") + kv.first.as<std::string>();
    if (kv.second.IsMap()) {
      Flatten(kv.second, key, name, out);
    } else {
      out->emplace_back(key, kv.second);
    }
  }
}

}  // namespace

std::vector<std::pair<std::string, YAML::Node>> ParseEntries(const std::string& text,
                                                             const std::string& name) {
  std::vector<std::pair<std::string, YAML::Node>> entries;
  try {
    const YAML::Node root = YAML::Load(text);
    if (root.IsNull()) return entries;  // an empty file keeps the defaults
    Flatten(root, "", name, &entries);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(name + ": invalid YAML: " + e.msg);
  }
  return entries;
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string Escape(std::string text) {
  for (std::size_t p = text.find('|'); p != std::string::npos; p = text.find('|', p + 2))
    text.replace(p, 1, "\\|");
  return text;
}

std::string Comment(const std::string& type, const std::string& unit, const std::string& range,
                    const std::string& doc) {
  std::string c;
  auto add = [&c](const std::string& part) {
    if (!part.empty()) c += (c.empty() ? "" : "; ") + part;
  };
  if (type.find('|') != std::string::npos) add(type);
  add(range);
  add(unit);
  add(doc);
  return c;
}

namespace {

std::pair<std::string, std::string> SplitKey(const std::string& key) {
  const std::size_t dot = key.find('.');
  if (dot == std::string::npos) return {"", key};
  return {key.substr(0, dot), key.substr(dot + 1)};
}

}  // namespace

std::string WriteYaml(const TableText& text, const std::vector<PrintedRow>& rows) {
  std::ostringstream out;
  out << "# plucker " << text.command
      << ": every option with its default. Generated from the options table\n"
         "# ("
      << text.source << ") by `plucker config " << text.command
      << "`; do not edit by hand.\n"
         "# Pass a copy with your changes via `plucker "
      << text.command
      << " --config FILE.yaml`; keys you leave out\n"
         "# keep their defaults. Unknown keys, wrong types and values out of range (the ranges\n"
         "# are in the comments) are errors naming the file and the key.\n";
  std::string group = "-";
  for (const PrintedRow& r : rows) {
    const auto [g, name] = SplitKey(r.key);
    if (g != group) {
      out << "\n";
      if (!g.empty()) {
        const auto comment = text.group_comments.find(g);
        out << g << ":";
        if (comment != text.group_comments.end()) out << "  # " << comment->second;
        out << "\n";
      }
      group = g;
    }
    const std::string indent = g.empty() ? "" : "  ";
    const std::string line = indent + name + ": " + r.value;
    std::string comment = Comment(r.type, r.unit, r.range, r.doc);
    if (!r.note.empty()) comment += " (" + r.note + ")";
    out << line << std::string(std::max<int>(1, 40 - static_cast<int>(line.size())), ' ') << "# "
        << comment << "\n";
  }
  return out.str();
}

std::string WriteMarkdown(const std::vector<PrintedRow>& rows) {
  std::ostringstream out;
  out << "| key | type | default | range | unit | meaning |\n|---|---|---|---|---|---|\n";
  for (const PrintedRow& r : rows) {
    out << "| `" << r.key << "` | " << Escape(r.type) << " | `" << r.value << "`"
        << (r.note.empty() ? "" : " (" + Escape(r.note) + ")") << " | " << Escape(r.range) << " | "
        << r.unit << " | " << Escape(r.doc) << " |\n";
  }
  return out.str();
}

}  // namespace options_internal
}  // namespace app
}  // namespace plucker
