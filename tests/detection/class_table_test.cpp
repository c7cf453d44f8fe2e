#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <string>

#include "sgslam/detection/detector_config.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

std::vector<std::string> Problems(const DetectorConfig& config) {
  ConfigChecker checker("detector");
  config.Validate(checker);
  return checker.problems();
}

bool Mentions(const std::vector<std::string>& problems, const std::string& text) {
  for (const auto& p : problems) {
    if (p.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(ClassTable, EveryCocoNameHasAWeight) {
  const auto names_file = test::SourceDir() / "models" / "yolo-fastest-1.1-coco" / "coco.names";
  std::ifstream in(names_file);
  std::set<std::string> names;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty()) names.insert(line);
  }
  ASSERT_EQ(names.size(), 80u);
  const auto table = DefaultDynamicWeights();
  for (const auto& name : names) EXPECT_EQ(table.count(name), 1u) << "no weight for '" << name << "'";
  EXPECT_EQ(table.size(), names.size()) << "the table names a class coco.names does not have";
}

TEST(ClassTable, PaperValuesAndDynamicClasses) {
  const ClassTable table{DetectorConfig{}};
  EXPECT_EQ(table.weight("person"), 5.0);  // paper Sec. III-D
  EXPECT_EQ(table.weight("chair"), 2.0);
  EXPECT_EQ(table.weight("tvmonitor"), 1.0);
  EXPECT_EQ(table.weight("no such class"), 1.0);
  EXPECT_TRUE(table.is_dynamic("person"));
  EXPECT_TRUE(table.is_dynamic("dog"));
  EXPECT_TRUE(table.is_dynamic("car"));
  EXPECT_FALSE(table.is_dynamic("chair"));  // weighted in Algorithm 1, but a static map object
  EXPECT_FALSE(table.is_dynamic("sofa"));
  EXPECT_FALSE(table.is_dynamic("no such class"));
  for (const auto& [name, w] : DefaultDynamicWeights()) {
    EXPECT_GE(w, 1.0) << name;
    EXPECT_LE(w, 5.0) << name;
  }
}

TEST(ClassTable, TheTableComesFromTheConfig) {
  DetectorConfig config;
  config.dynamic_weight = {{"chair", 3.0}, {"robot", 4.5}, {"cart", 2.0}};
  const ClassTable table(config);
  EXPECT_TRUE(table.is_dynamic("chair"));
  EXPECT_TRUE(table.is_dynamic("robot"));
  EXPECT_FALSE(table.is_dynamic("cart"));  // below ClassTable::kMinWeight
  EXPECT_EQ(table.weight("cart"), 2.0);
  EXPECT_EQ(table.weight("person"), 1.0);  // a YAML table replaces the defaults
  EXPECT_FALSE(table.is_dynamic("person"));
}

TEST(DetectorConfig, DefaultsValidate) { EXPECT_TRUE(Problems(DetectorConfig{}).empty()); }

TEST(DetectorConfig, BadValuesAreRejectedWithTheKey) {
  DetectorConfig c;
  c.backend = "gpu";
  c.model = "../elsewhere/yolo";
  c.input_size = 300;  // not a multiple of 32
  c.score_threshold = 1.5;
  c.person_score_threshold = 0.0;
  c.threads = -1;
  c.timeout_ms = -5;
  c.dynamic_weight["person"] = 6.0;
  c.dynamic_weight["chair"] = 0.5;
  const auto problems = Problems(c);
  for (const char* key :
       {"detector.backend = gpu", "detector.model = ", "detector.input_size = 300", "detector.score_threshold = 1.5",
        "detector.person_score_threshold = 0", "detector.threads = -1", "detector.timeout_ms = -5",
        "detector.dynamic_weight.person = 6",
        "detector.dynamic_weight.chair = 0.5"}) {
    EXPECT_TRUE(Mentions(problems, key)) << "no problem reported for " << key;
  }
  EXPECT_EQ(problems.size(), 9u);
}

TEST(DetectorConfig, VisitListsEveryField) {
  DetectorConfig c;
  std::set<std::string> keys;
  c.Visit([&](const char* key, auto&, const char* unit) {
    EXPECT_NE(std::string(unit), "") << key;
    keys.insert(key);
  });
  EXPECT_EQ(keys, (std::set<std::string>{"backend", "model_dir", "model", "input_size", "score_threshold",
                                         "person_score_threshold", "threads", "timeout_ms", "stride",
                                         "detections_file", "dynamic_weight"}));
}

}  // namespace
}  // namespace sgslam
