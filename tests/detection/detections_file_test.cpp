#include "sgslam/detection/detections_file.h"

#include <gtest/gtest.h>

#include "sgslam/common/error.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

Detection Make(int id, const std::string& name, float score, float x, float y, float w, float h) {
  Detection d;
  d.class_id = id;
  d.class_name = name;
  d.score = score;
  d.box = cv::Rect2f(x, y, w, h);
  return d;
}

TEST(DetectionsFile, RoundTripKeepsEveryFieldAndNamesWithSpaces) {
  test::TempDir dir;
  const Timestamp t0 = 1'700'000'000 * kNsPerSecond + 33'333'000;
  const Timestamp t1 = t0 + 33'334'000;
  const std::vector<FrameDetections> frames = {
      {t0, {Make(0, "person", 1.f, 10, 20, 100.5f, 200), Make(58, "potted plant", 0.25f, 0, 0, 640, 480)}},
      {t1, {}},
      {t1 + 1000, {Make(56, "chair", 0.875f, 300.25f, 100, 20, 30)}}};
  const auto path = dir / "detections.txt";
  WriteDetectionsFile(path, frames);
  const auto read = ReadDetectionsFile(path);
  ASSERT_EQ(read.size(), 2u);  // a frame without detections leaves no line
  for (const auto& [t, expected] : frames) {
    if (expected.empty()) {
      EXPECT_EQ(read.count(t), 0u);
      continue;
    }
    ASSERT_EQ(read.count(t), 1u);
    const auto& got = read.at(t);
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
      EXPECT_EQ(got[i].class_id, expected[i].class_id);
      EXPECT_EQ(got[i].class_name, expected[i].class_name);
      EXPECT_FLOAT_EQ(got[i].score, expected[i].score);
      EXPECT_NEAR(got[i].box.x, expected[i].box.x, 1e-3);
      EXPECT_NEAR(got[i].box.y, expected[i].box.y, 1e-3);
      EXPECT_NEAR(got[i].box.width, expected[i].box.width, 1e-3);
      EXPECT_NEAR(got[i].box.height, expected[i].box.height, 1e-3);
    }
  }
}

TEST(DetectionsFile, SkipsCommentsAndBlankLines) {
  test::TempDir dir;
  test::WriteText(dir / "d.txt",
                  "# header\n\n  # indented comment\n1.5 0 0.9 1 2 3 4 person\r\n2.0 62 0.5 5 6 7 8  tv monitor  \n");
  const auto read = ReadDetectionsFile(dir / "d.txt");
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read.at(1'500'000'000).at(0).class_name, "person");
  const Detection& tv = read.at(2'000'000'000).at(0);
  EXPECT_EQ(tv.class_name, "tv monitor");
  EXPECT_EQ(tv.class_id, 62);
  EXPECT_FLOAT_EQ(tv.box.width, 2.f);
}

TEST(DetectionsFile, MalformedLinesNameFileAndLine) {
  const std::vector<std::string> bad = {
      "1.0 0 0.9 1 2 3 person",      // a field missing
      "1.0 0 0.9 1 2 3 4",           // no class name
      "abc 0 0.9 1 2 3 4 person",    // bad timestamp
      "1.0 x 0.9 1 2 3 4 person",    // bad class id
      "1.0 1.5 0.9 1 2 3 4 person",  // class id not an integer
      "1.0 0 0.9 1 2 3 nan person",  // not finite
      "1.0 0 0.9 5 2 3 4 person",    // x1 < x0
      "1.0 0 0.9 -1e30 0 1e30 4 person",  // beyond int once in pixels
  };
  for (const std::string& line : bad) {
    test::TempDir dir;
    const auto path = dir / "d.txt";
    test::WriteText(path, "# ok\n1.0 0 0.9 1 2 3 4 person\n" + line + "\n");
    try {
      ReadDetectionsFile(path);
      ADD_FAILURE() << "no error for: " << line;
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find(path.string() + ":3:"), std::string::npos) << e.what();
    }
  }
}

// Values that parse as numbers but not as a detection: a score of 1e300 became an
// infinite float, and corners of 3e38 an infinite width, or beyond int's range where
// the dynamic masks cast them (the fuzz target checks every detection it gets).
TEST(DetectionsFile, ScoresAndCornersOutOfRangeNameTheValue) {
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"1.0 0 1e300 1 2 3 4 person", "score"},
      {"1.0 0 -0.1 1 2 3 4 person", "score"},
      {"1.0 0 0.9 -3e38 2 3e38 4 person", "x0 = -3e38"},
      {"1.0 0 0.9 1 2 3 1e10 person", "y1 = 1e10"},
  };
  for (const auto& [line, named] : bad) {
    test::TempDir dir;
    const auto path = dir / "d.txt";
    test::WriteText(path, "1.0 0 0.9 -1000 -5 1e6 4 person\n" + line + "\n");
    try {
      ReadDetectionsFile(path);
      ADD_FAILURE() << "no error for: " << line;
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find(path.string() + ":2:"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
    }
  }
}

TEST(DetectionsFile, MissingFileIsAnInputError) {
  test::TempDir dir;
  EXPECT_THROW(ReadDetectionsFile(dir / "none.txt"), InputError);
}

}  // namespace
}  // namespace sgslam
