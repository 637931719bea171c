// The options table of `plucker lidar`: every entry round-trips through YAML, the committed
// defaults file and the documentation table are what the table prints, and bad files get errors
// naming the file and the key.
#include "lidar_options_table.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace plucker {
namespace app {
namespace {

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A value different from `text` of the same type (for choices: the next choice).
std::string OtherValue(const LidarOption& o, const std::string& text) {
  if (o.type == "number") return std::to_string(std::stod(text) * 1.5 + 0.25);
  if (o.type == "integer") return std::to_string(std::stoi(text) + 3);
  if (o.type == "bool") return text == "true" ? "false" : "true";
  std::vector<std::string> choices;
  std::stringstream s(o.type);
  for (std::string c; s >> c;)
    if (c != "|") choices.push_back(c);
  for (std::size_t i = 0; i < choices.size(); ++i)
    if (choices[i] == text) return choices[(i + 1) % choices.size()];
  return "";
}

TEST(LidarOptionsTable, KeysAreUniqueAndDocumented) {
  const std::vector<LidarOption>& table = LidarOptionTable();
  ASSERT_GE(table.size(), 50u);  // every LidarOdometryOptions field a config file may set
  std::set<std::string> keys;
  for (const LidarOption& o : table) {
    EXPECT_TRUE(keys.insert(o.key).second) << o.key;
    EXPECT_FALSE(o.doc.empty()) << o.key;
    EXPECT_TRUE(o.get && o.set) << o.key;
  }
}

TEST(LidarOptionsTable, EveryEntryRoundTripsThroughYaml) {
  const LidarConfig defaults;
  int changed = 0;
  for (const LidarOption& o : LidarOptionTable()) {
    const std::string before = o.get(defaults);
    const std::string value = OtherValue(o, before);
    ASSERT_FALSE(value.empty()) << o.key;
    LidarConfig config;
    ApplyLidarConfigYaml(o.key.substr(0, o.key.find('.')) == o.key
                             ? o.key + ": " + value
                             : o.key.substr(0, o.key.find('.')) + ":\n  " +
                                   o.key.substr(o.key.find('.') + 1) + ": " + value,
                         "one.yaml", &config);
    EXPECT_NE(o.get(config), before) << o.key << " was not set by the YAML";
    // The whole configuration written out and read back into defaults gives the same values.
    LidarConfig reread;
    ApplyLidarConfigYaml(LidarConfigYaml(config), "all.yaml", &reread);
    for (const LidarOption& p : LidarOptionTable())
      EXPECT_EQ(p.get(reread), p.get(config)) << "after setting " << o.key << ", " << p.key;
    ++changed;
  }
  EXPECT_EQ(changed, static_cast<int>(LidarOptionTable().size()));
}

TEST(LidarOptionsTable, DefaultsFileIsTheTablesOutput) {
  const std::string path = std::string(PLUCKER_SOURCE_DIR) + "/config/lidar_default.yaml";
  EXPECT_EQ(ReadText(path), LidarConfigYaml(LidarConfig()))
      << path << " is stale: run scripts/update_lidar_options.sh";
  LidarConfig config;
  LoadLidarConfig(path, &config);
  for (const LidarOption& o : LidarOptionTable()) EXPECT_EQ(o.get(config), o.get(LidarConfig()));
}

TEST(LidarOptionsTable, DocumentationTableIsTheTablesOutput) {
  const std::string path = std::string(PLUCKER_SOURCE_DIR) + "/docs/lidar-odometry.md";
  const std::string doc = ReadText(path);
  const std::string begin = "<!-- options table begin", end = "<!-- options table end -->";
  const std::size_t b = doc.find(begin), e = doc.find(end);
  ASSERT_NE(b, std::string::npos) << path;
  ASSERT_NE(e, std::string::npos) << path;
  const std::size_t body = doc.find('\n', b) + 1;
  EXPECT_EQ(doc.substr(body, e - body), LidarOptionsMarkdown())
      << path << " is stale: run scripts/update_lidar_options.sh";
}

std::string ErrorOf(const std::string& yaml) {
  LidarConfig config;
  try {
    ApplyLidarConfigYaml(yaml, "bad.yaml", &config);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(LidarOptionsTable, BadFilesNameTheFileAndTheKey) {
  EXPECT_EQ(ErrorOf("features:\n  min_rang: 1.0\n"), "bad.yaml: unknown key 'features.min_rang'");
  EXPECT_EQ(ErrorOf("nothing: 1\n"), "bad.yaml: unknown key 'nothing'");
  EXPECT_EQ(ErrorOf("registration:\n  max_iterations: abc\n"),
            "bad.yaml: key 'registration.max_iterations': expected an integer, got 'abc'");
  EXPECT_EQ(ErrorOf("features:\n  min_range: near\n"),
            "bad.yaml: key 'features.min_range': expected a number, got 'near'");
  EXPECT_EQ(ErrorOf("degeneracy:\n  handle: maybe\n"),
            "bad.yaml: key 'degeneracy.handle': expected true or false, got 'maybe'");
  EXPECT_EQ(ErrorOf("registration:\n  loss: l2\n"),
            "bad.yaml: key 'registration.loss': expected huber | cauchy | none, got 'l2'");
  EXPECT_EQ(ErrorOf("features: 3\n"), "bad.yaml: unknown key 'features'");
  EXPECT_EQ(ErrorOf("[1, 2]\n"), "bad.yaml: top level must be a mapping");
  EXPECT_NE(ErrorOf("features: [\n").find("bad.yaml: invalid YAML"), std::string::npos);
  EXPECT_EQ(ErrorOf(""), "");
}

}  // namespace
}  // namespace app
}  // namespace plucker
