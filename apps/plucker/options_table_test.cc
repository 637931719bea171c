// The options tables of `plucker lidar`, `vo` and `vio` (options_table.h): every entry
// round-trips through YAML, the committed defaults files and documentation tables are what the
// tables print, values out of range and renamed keys are errors, bad files get errors naming the
// file and the key, and the options vo and vio share have one key, unit, doc and range.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "lidar_options_table.h"
#include "vio_config.h"
#include "vo_config.h"

namespace plucker {
namespace app {
namespace {

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A value of the row's type, different from `text` and accepted by the row (in range).
template <typename Config>
std::string OtherValue(const OptionRow<Config>& o, const std::string& text) {
  std::vector<std::string> candidates;
  if (o.type == "number") {
    const double v = std::stod(text);
    for (double c : {v * 1.5 + 0.25, v * 0.5, v + 0.1, v - 0.1, 0.5, 0.0})
      candidates.push_back(options_internal::FormatNumber(c));
  } else if (o.type == "integer") {
    const int v = std::stoi(text);
    for (int c : {v + 3, v + 1, v - 1, 0, 1}) candidates.push_back(std::to_string(c));
  } else if (o.type == "bool") {
    candidates.push_back(text == "true" ? "false" : "true");
  } else if (o.type == "list") {
    candidates.push_back("[0.1, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]");  // a pose
    candidates.push_back("[0.1, -0.2, 0.3]");                     // a 3-vector
  } else {
    std::stringstream s(o.type);
    for (std::string c; s >> c;)
      if (c != "|" && c != text) candidates.push_back(c);
  }
  for (const std::string& c : candidates) {
    Config probe;
    try {
      o.set(YAML::Load(c), &probe);
    } catch (const std::invalid_argument&) {
      continue;
    }
    if (o.get(probe) != text) return c;
  }
  return "";
}

// `key: value` as nested YAML ("a.b: v" -> "a:\n  b: v").
std::string Nested(const std::string& key, const std::string& value) {
  const std::size_t dot = key.find('.');
  if (dot == std::string::npos) return key + ": " + value;
  return key.substr(0, dot) + ":\n  " + key.substr(dot + 1) + ": " + value;
}

template <typename Config>
void ExpectKeysUniqueAndDocumented(const OptionsTable<Config>& table) {
  std::set<std::string> keys;
  for (const OptionRow<Config>& o : table.rows()) {
    EXPECT_TRUE(keys.insert(o.key).second) << o.key;
    EXPECT_FALSE(o.doc.empty()) << o.key;
    EXPECT_TRUE(o.get && o.set) << o.key;
    if (o.type == "number" || o.type == "integer") {
      EXPECT_FALSE(o.range.empty()) << o.key;
    }
  }
  for (const auto& [old_key, new_key] : table.text().renamed) {
    EXPECT_EQ(keys.count(old_key), 0u) << old_key << " is renamed and a key";
    EXPECT_EQ(keys.count(new_key), 1u) << old_key << " renamed to the unknown " << new_key;
  }
}

template <typename Config>
void ExpectRoundTrips(const OptionsTable<Config>& table, const Config& defaults) {
  for (const OptionRow<Config>& o : table.rows()) {
    const std::string before = o.get(defaults);
    const std::string value = OtherValue(o, before);
    ASSERT_FALSE(value.empty()) << o.key;
    Config config = defaults;
    table.Apply(Nested(o.key, value), "one.yaml", &config);
    EXPECT_NE(o.get(config), before) << o.key << " was not set by the YAML";
    Config dotted = defaults;  // the dotted spelling sets the same
    table.Apply(o.key + ": " + value, "dotted.yaml", &dotted);
    EXPECT_EQ(o.get(dotted), o.get(config)) << o.key;
    // The whole configuration written out and read back into defaults gives the same values.
    Config reread = defaults;
    table.Apply(table.Yaml(config), "all.yaml", &reread);
    for (const OptionRow<Config>& p : table.rows())
      EXPECT_EQ(p.get(reread), p.get(config)) << "after setting " << o.key << ", " << p.key;
  }
}

template <typename Config>
std::string ErrorOf(const OptionsTable<Config>& table, const std::string& yaml) {
  Config config;
  try {
    table.Apply(yaml, "bad.yaml", &config);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

// The committed file and the docs table between its markers are the table's output.
void ExpectGenerated(const std::string& file, const std::string& yaml, const std::string& doc,
                     const std::string& markdown) {
  const std::string path = std::string(PLUCKER_SOURCE_DIR) + "/" + file;
  EXPECT_EQ(ReadText(path), yaml) << path << " is stale: run scripts/update_options.sh";
  const std::string doc_path = std::string(PLUCKER_SOURCE_DIR) + "/" + doc;
  const std::string text = ReadText(doc_path);
  const std::string begin = "<!-- options table begin", end = "<!-- options table end -->";
  const std::size_t b = text.find(begin), e = text.find(end);
  ASSERT_NE(b, std::string::npos) << doc_path;
  ASSERT_NE(e, std::string::npos) << doc_path;
  const std::size_t body = text.find('\n', b) + 1;
  EXPECT_EQ(text.substr(body, e - body), markdown)
      << doc_path << " is stale: run scripts/update_options.sh";
}

TEST(OptionsTable, RangesPrintAndCheck) {
  EXPECT_EQ(Between(2, 1000).Text(), "[2, 1000]");
  EXPECT_EQ(AtLeast(0.0).Text(), ">= 0");
  EXPECT_EQ(Above(0.0).Text(), "> 0");
  EXPECT_EQ((Range{0.0, 1.0, true}).Text(), "(0, 1]");
  EXPECT_EQ(Between(0.0, 0.5).Text(), "[0, 0.5]");
  EXPECT_EQ(AnyValue().Text(), "any");
  EXPECT_TRUE(Above(0.0).Contains(1e-9));
  EXPECT_FALSE(Above(0.0).Contains(0.0));
  EXPECT_TRUE(AtLeast(0.0).Contains(0.0));
  EXPECT_FALSE(Between(2, 1000).Contains(1001));
}

TEST(OptionsTable, KeysAreUniqueAndDocumented) {
  ExpectKeysUniqueAndDocumented(LidarOptions());
  ExpectKeysUniqueAndDocumented(VoOptions());
  ExpectKeysUniqueAndDocumented(VioOptions());
  EXPECT_GE(LidarOptions().rows().size(), 50u);  // every LidarOdometryOptions field
  EXPECT_GE(VoOptions().rows().size(), 35u);
  EXPECT_GE(VioOptions().rows().size(), 30u);
}

TEST(OptionsTable, EveryEntryRoundTripsThroughYaml) {
  ExpectRoundTrips(LidarOptions(), LidarConfig());
  ExpectRoundTrips(VoOptions(), FeaturesVoConfig());
  ExpectRoundTrips(VoOptions(), ImageVoConfig());
  ExpectRoundTrips(VioOptions(), VioConfig());
}

TEST(OptionsTable, DefaultsAreInRange) {  // every default read back through its row's checks
  LidarConfig lidar;
  LidarOptions().Apply(LidarConfigYaml(LidarConfig()), "lidar", &lidar);
  VoConfig vo = ImageVoConfig();
  VoOptions().Apply(VoOptions().Yaml(ImageVoConfig()), "vo", &vo);
  VioConfig vio;
  VioOptions().Apply(VioOptions().Yaml(VioConfig()), "vio", &vio);
  EXPECT_NO_THROW(CheckVioConfig(vio, "vio"));
  EXPECT_NO_THROW(vo.Check());
}

TEST(OptionsTable, GeneratedFilesAreTheTablesOutput) {
  ExpectGenerated("config/lidar_default.yaml", LidarConfigYaml(LidarConfig()),
                  "docs/lidar-odometry.md", LidarOptionsMarkdown());
  ExpectGenerated("config/vo_default.yaml",
                  VoOptions().Yaml(FeaturesVoConfig(), VoImageDefaultNote), "docs/vo.md",
                  VoOptions().Markdown(FeaturesVoConfig(), VoImageDefaultNote));
  ExpectGenerated("config/vio_default.yaml", VioOptions().Yaml(VioConfig()), "docs/vio.md",
                  VioOptions().Markdown(VioConfig()));
}

TEST(OptionsTable, SharedVisualOptionsAreOneOptionInVoAndVio) {
  int shared = 0;
  for (const OptionRow<VoConfig>& v : VoOptions().rows()) {
    const OptionRow<VioConfig>* i = VioOptions().Find(v.key);
    if (i == nullptr) continue;
    ++shared;
    EXPECT_EQ(i->type, v.type) << v.key;
    EXPECT_EQ(i->unit, v.unit) << v.key;
    EXPECT_EQ(i->doc, v.doc) << v.key;
    EXPECT_EQ(i->range, v.range) << v.key;
  }
  EXPECT_EQ(shared, 18);  // use_lines, 11 window.*, 3 points.*, 3 lines.*
}

TEST(OptionsTable, VioMinLineViewsReachesTheWindow) {
  VioConfig c;
  EXPECT_EQ(odometry::WindowOptions(c.odometry, {}).min_line_views, 2);  // the default: main's
  VioOptions().Apply("window:\n  min_line_views: 3\n", "x.yaml", &c);
  EXPECT_EQ(c.odometry.min_line_views, 3);
  EXPECT_EQ(odometry::WindowOptions(c.odometry, {}).min_line_views, 3);
  EXPECT_EQ(ErrorOf(VioOptions(), "window:\n  min_line_views: 1\n"),
            "bad.yaml: key 'window.min_line_views': value 1 out of range [2, 1000]");
  c.odometry.min_line_views = 1;
  EXPECT_NE(c.odometry.Problem().find("min_line_views >= 2"), std::string::npos);
}

TEST(OptionsTable, VioTwoViewLineOptionsReachTheWindow) {
  VioConfig c;
  const window::SlidingWindowOptions d = odometry::WindowOptions(c.odometry, {});
  EXPECT_EQ(d.two_view_line_sigma_scale, 1.0);  // the defaults: main's
  EXPECT_FALSE(d.recheck_two_view_lines);
  EXPECT_EQ(c.odometry.init_two_view_line_sigma_scale, 0.0);
  VioOptions().Apply(
      "window:\n  two_view_line_sigma_scale: 3\n  recheck_two_view_lines: true\n"
      "init:\n  two_view_line_sigma_scale: 10\n",
      "x.yaml", &c);
  const window::SlidingWindowOptions o = odometry::WindowOptions(c.odometry, {});
  EXPECT_EQ(o.two_view_line_sigma_scale, 3.0);
  EXPECT_TRUE(o.recheck_two_view_lines);
  EXPECT_EQ(c.odometry.init_two_view_line_sigma_scale, 10.0);
  EXPECT_TRUE(c.odometry.Problem().empty());
  c.odometry.init_two_view_line_sigma_scale = 0.5;
  EXPECT_NE(c.odometry.Problem().find("init_two_view_line_sigma_scale 0 or >= 1"),
            std::string::npos);
  EXPECT_EQ(ErrorOf(VioOptions(), "window:\n  two_view_line_sigma_scale: 0.5\n"),
            "bad.yaml: key 'window.two_view_line_sigma_scale': value 0.5 out of range >= 1");
}

TEST(OptionsTable, UseLinesSetsEveryLineSwitch) {
  VoConfig vo = ImageVoConfig();
  VoOptions().Apply("use_lines: false", "f.yaml", &vo);
  EXPECT_FALSE(vo.window.use_lines);
  EXPECT_FALSE(vo.frontend.use_lines);
  VioConfig vio;
  VioOptions().Apply("use_lines: false", "f.yaml", &vio);
  EXPECT_FALSE(vio.odometry.use_lines);
}

TEST(OptionsTable, LidarBadFilesNameTheFileAndTheKey) {
  const LidarOptionsTable& t = LidarOptions();
  EXPECT_EQ(ErrorOf(t, "features:\n  min_rang: 1.0\n"),
            "bad.yaml: unknown key 'features.min_rang'");
  EXPECT_EQ(ErrorOf(t, "nothing: 1\n"), "bad.yaml: unknown key 'nothing'");
  EXPECT_EQ(ErrorOf(t, "registration:\n  max_iterations: abc\n"),
            "bad.yaml: key 'registration.max_iterations': expected an integer, got 'abc'");
  EXPECT_EQ(ErrorOf(t, "features:\n  min_range: near\n"),
            "bad.yaml: key 'features.min_range': expected a number, got 'near'");
  EXPECT_EQ(ErrorOf(t, "degeneracy:\n  handle: maybe\n"),
            "bad.yaml: key 'degeneracy.handle': expected true or false, got 'maybe'");
  EXPECT_EQ(ErrorOf(t, "registration:\n  loss: l2\n"),
            "bad.yaml: key 'registration.loss': expected huber | cauchy | none, got 'l2'");
  EXPECT_EQ(ErrorOf(t, "registration:\n  num_neighbours: 40\n"),
            "bad.yaml: key 'registration.num_neighbours': value 40 out of range [3, 16]");
  EXPECT_EQ(ErrorOf(t, "features:\n  scan_period: 0\n"),
            "bad.yaml: key 'features.scan_period': value 0 out of range > 0");
  EXPECT_EQ(ErrorOf(t, "features:\n  min_range: .nan\n"),
            "bad.yaml: key 'features.min_range': value .nan out of range >= 0");
  EXPECT_EQ(ErrorOf(t, "features: 3\n"), "bad.yaml: unknown key 'features'");
  EXPECT_EQ(ErrorOf(t, "[1, 2]\n"), "bad.yaml: top level must be a mapping");
  EXPECT_NE(ErrorOf(t, "features: [\n").find("bad.yaml: invalid YAML"), std::string::npos);
  EXPECT_EQ(ErrorOf(t, ""), "");
}

TEST(OptionsTable, VoBadFilesNameTheFileAndTheKey) {
  const OptionsTable<VoConfig>& t = VoOptions();
  EXPECT_EQ(ErrorOf(t, "window:\n  sise: 5\n"), "bad.yaml: unknown key 'window.sise'");
  EXPECT_EQ(ErrorOf(t, "window.size: 1\n"),
            "bad.yaml: key 'window.size': value 1 out of range [2, 1000]");
  EXPECT_EQ(ErrorOf(t, "window:\n  size: ten\n"),
            "bad.yaml: key 'window.size': expected an integer, got 'ten'");
  EXPECT_EQ(ErrorOf(t, "lines:\n  detection_scale: 0\n"),
            "bad.yaml: key 'lines.detection_scale': value 0 out of range (0, 1]");
  EXPECT_EQ(ErrorOf(t, "window:\n  use_lines: false\n"),
            "bad.yaml: key 'window.use_lines' was renamed to 'use_lines'");
  EXPECT_EQ(ErrorOf(t, "lines.enabled: false\n"),
            "bad.yaml: key 'lines.enabled' was renamed to 'use_lines'");
  EXPECT_EQ(ErrorOf(t, "window:\n  size: [1, 2]\n"),
            "bad.yaml: key 'window.size': expected an integer, got 'a non-scalar'");
}

TEST(OptionsTable, VioBadFilesNameTheFileAndTheKey) {
  const OptionsTable<VioConfig>& t = VioOptions();
  EXPECT_EQ(ErrorOf(t, "windw: 5\n"), "bad.yaml: unknown key 'windw'");
  EXPECT_EQ(ErrorOf(t, "window: 5\n"), "bad.yaml: key 'window' was renamed to 'window.size'");
  EXPECT_EQ(ErrorOf(t, "max_point_tracks: 5\n"),
            "bad.yaml: key 'max_point_tracks' was renamed to 'points.max_tracks'");
  EXPECT_EQ(ErrorOf(t, "max_keyframe_interval_s: 0.5\n"),
            "bad.yaml: key 'max_keyframe_interval_s' was renamed to "
            "'inertial.max_imu_factor_span_s'");
  EXPECT_EQ(ErrorOf(t, "inertial:\n  gyro_bias_prior_sigma: 0\n"),
            "bad.yaml: key 'inertial.gyro_bias_prior_sigma': value 0 out of range > 0");
  EXPECT_EQ(ErrorOf(t, "time_offset:\n  initial_s: 1.5\n"),
            "bad.yaml: key 'time_offset.initial_s': value 1.5 out of range (-1, 1]");
  EXPECT_EQ(ErrorOf(t, "lines:\n  flow_samples: -1\n"),
            "bad.yaml: key 'lines.flow_samples': value -1 out of range [0, 1000]");
  EXPECT_EQ(ErrorOf(t, "extrinsic:\n  T_b_c: [1, 2, 3]\n"),
            "bad.yaml: key 'extrinsic.T_b_c': expected 7 finite numbers [tx, ty, tz, qx, qy, qz, "
            "qw] with a non-zero quaternion");
  EXPECT_EQ(ErrorOf(t, "extrinsic:\n  T_b_c: 3\n"),
            "bad.yaml: key 'extrinsic.T_b_c': expected a list of 7 numbers [tx, ty, tz, qx, qy, "
            "qz, qw]");
  VioConfig c;
  VioOptions().Apply("init:\n  min_keyframes: 12\n  max_keyframes: 10\n", "x.yaml", &c);
  try {
    CheckVioConfig(c, "x.yaml");
    ADD_FAILURE() << "init.max_keyframes < init.min_keyframes accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "x.yaml: key 'init.max_keyframes' (10) must be >= init.min_keyframes (12)");
  }
}

TEST(OptionsTable, FlagsGoThroughTheSameChecks) {
  VioConfig c;
  VioOptions().Set("window.size", "12", "--window", &c);
  EXPECT_EQ(c.odometry.window, 12);
  try {
    VioOptions().Set("window.size", "1", "--window", &c);
    ADD_FAILURE() << "--window 1 accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "--window: key 'window.size': value 1 out of range [2, 1000]");
  }
}

}  // namespace
}  // namespace app
}  // namespace plucker
