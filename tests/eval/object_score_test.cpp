// Scoring an object map against true objects (eval/object_score.h).
#include "sgslam/eval/object_score.h"

#include <gtest/gtest.h>

#include <fstream>

#include "sgslam/common/error.h"
#include "support/test_support.h"

namespace sgslam::eval {
namespace {

ObjectEstimate Estimate(int id, const std::string& cls, const Eigen::Vector3d& c, const Eigen::Vector3d& size) {
  ObjectEstimate e;
  e.id = id;
  e.class_name = cls;
  e.centroid = c;
  e.size = size;
  e.exported = true;
  return e;
}

TEST(ObjectScore, MatchesOneToOneAndCountsDuplicatesFalseAndUnscored) {
  std::vector<TrueObject> truth(4);
  truth[0] = {1, "tvmonitor", {0, 0, 1}, {0.5, 0.1, 0.4}, true};
  truth[1] = {2, "keyboard", {0, 0.3, 0.8}, {0.45, 0.15, 0.03}, true};
  truth[2] = {3, "whiteboard", {2, 0, 1.5}, {1.0, 0.02, 0.8}, false};  // no COCO class
  truth[3] = {4, "chair", {-1, -1, 0.5}, {0.5, 0.5, 1.0}, true};       // missed
  const std::vector<ObjectEstimate> est = {
      Estimate(10, "tvmonitor", {0.05, 0, 1}, {0.5, 0.1, 0.4}),  // right
      Estimate(11, "laptop", {0.0, 0.32, 0.8}, {0.45, 0.15, 0.03}),  // the keyboard, named wrong
      Estimate(12, "tvmonitor", {0.2, 0.05, 1}, {0.3, 0.1, 0.3}),    // the monitor again
      Estimate(13, "book", {2, 0.1, 1.5}, {0.3, 0.1, 0.3}),          // on the whiteboard
      Estimate(14, "cup", {5, 5, 1}, {0.1, 0.1, 0.1}),               // nothing there
  };
  const ObjectScore s = ScoreObjects(truth, est);
  EXPECT_EQ(s.truths, 3);
  EXPECT_EQ(s.matched, 2);
  EXPECT_EQ(s.duplicates, 1);
  EXPECT_EQ(s.false_positives, 1);
  EXPECT_EQ(s.unscored, 1);
  EXPECT_DOUBLE_EQ(s.precision, 2.0 / 4.0);
  EXPECT_DOUBLE_EQ(s.recall, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.class_accuracy, 0.5);
  EXPECT_NEAR(s.median_centroid_error, (0.05 + 0.02) / 2, 1e-9);
  EXPECT_NEAR(s.median_size_error, 0.0, 1e-9);
  ASSERT_EQ(s.missed, std::vector<int>{4});
  EXPECT_EQ(s.matches[0].truth_id, 1);
  EXPECT_EQ(s.matches[1].truth_id, 2);
  EXPECT_EQ(s.matches[2].kind, ObjectMatch::kDuplicate);
  EXPECT_EQ(s.matches[3].kind, ObjectMatch::kUnscored);
  EXPECT_EQ(s.matches[4].kind, ObjectMatch::kFalse);
}

TEST(ObjectScore, ReadsBothListsAndNamesWhatIsWrong) {
  const test::TempDir dir;
  const auto write = [&](const std::string& text) {
    std::ofstream(dir / "truth.json") << text;
    return dir / "truth.json";
  };
  const auto ok = LoadObjectTruth(write(
      R"({"objects": [{"id": 3, "class": "chair", "centroid": [1, 2, 0.5], "size": [0.5, 0.5, 1], "dynamic": false},
                      {"class": "person", "centroid": [0, 0, 1], "size": [0.4, 0.3, 1.7], "static": false},
                      {"class": "whiteboard", "coco": false, "centroid": [0, 0, 1], "size": [1, 0, 1]},
                      {"class": "person", "dynamic": true, "size": [0.68, 0.28, 1.75]}]})"));  // a walker: no place
  ASSERT_EQ(ok.size(), 3u);
  EXPECT_EQ(ok[0].id, 3);
  EXPECT_TRUE(ok[0].scored);
  EXPECT_FALSE(ok[1].scored);
  EXPECT_FALSE(ok[2].scored);
  EXPECT_THROW(LoadObjectTruth(write("[1, 2]")), InputError);
  EXPECT_THROW(LoadObjectTruth(write(R"({"objects": [{"class": "chair", "size": [0.5, 0.5, 1]}]})")), InputError);
  try {
    LoadObjectTruth(write(R"({"objects": [{"class": "cup", "centroid": [1, 2], "size": [0.1, 0.1, 0.1]}]})"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("object 1: \"centroid\""), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sgslam::eval
