#include "sgslam/detection/file_detector.h"

#include <gtest/gtest.h>

#include "sgslam/common/error.h"
#include "sgslam/detection/detections_file.h"
#include "sgslam/synth/writer.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

constexpr Timestamp kT0 = 1305031229'528748000;  // ns
constexpr Timestamp kMs = 1'000'000;

void ExpectSame(const std::vector<Detection>& got, const std::vector<Detection>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].class_id, want[i].class_id);
    EXPECT_EQ(got[i].class_name, want[i].class_name);
    EXPECT_EQ(got[i].score, want[i].score);
    EXPECT_EQ(got[i].box, want[i].box);
  }
}

TEST(FileDetector, ReturnsTheBoxesOfTheFrameWithTheSameTimestamp) {
  test::TempDir dir;
  test::WriteText(dir / "detections.txt",
                  "# timestamp class_id score x0 y0 x1 y1 class_name\n"
                  "1305031229.528748 0 0.900 10.500 20.000 110.500 220.000 person\n"
                  "1305031229.528748 58 0.250 0.000 0.000 640.000 480.000 pottedplant\n"
                  "1305031229.561620 56 0.875 300.250 100.000 320.250 130.000 chair\n");
  FileDetector detector(dir / "detections.txt");
  const cv::Mat no_image;
  const auto first = detector.Detect(no_image, kT0);
  ASSERT_EQ(first.size(), 2u);
  EXPECT_EQ(first[0].class_id, 0);
  EXPECT_EQ(first[0].class_name, "person");
  EXPECT_FLOAT_EQ(first[0].score, 0.9f);
  EXPECT_EQ(first[0].box, cv::Rect2f(10.5f, 20.f, 100.f, 200.f));
  EXPECT_EQ(first[1].class_name, "pottedplant");
  EXPECT_EQ(first[1].box, cv::Rect2f(0, 0, 640, 480));

  // Within 1 ms on either side: the same frame.
  ExpectSame(detector.Detect(no_image, kT0 + kMs), first);
  ExpectSame(detector.Detect(no_image, kT0 - kMs + 1), first);
  const auto second = detector.Detect(no_image, kT0 + 32'872'000);
  ASSERT_EQ(second.size(), 1u);
  EXPECT_EQ(second[0].class_name, "chair");
  EXPECT_EQ(second[0].box, cv::Rect2f(300.25f, 100.f, 20.f, 30.f));

  // Frames the file does not list, or more than 1 ms away: no detections.
  EXPECT_TRUE(detector.Detect(no_image, kT0 + kMs + 1).empty());
  EXPECT_TRUE(detector.Detect(no_image, kT0 - 2 * kMs).empty());
  EXPECT_TRUE(detector.Detect(no_image, kT0 + 16 * kMs).empty());
  EXPECT_TRUE(detector.Detect(no_image, 0).empty());
  EXPECT_NE(detector.Describe().find("detections.txt"), std::string::npos);
}

TEST(FileDetector, MissingFileNamesIt) {
  test::TempDir dir;
  const auto missing = dir / "nowhere" / "detections.txt";
  try {
    FileDetector detector(missing);
    FAIL() << "no error for a missing file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
}

TEST(FileDetector, MakeDetectorFindsTheDatasetFileAndNoneGivesNull) {
  test::TempDir dir;
  DetectorConfig config;
  config.backend = "none";
  EXPECT_EQ(MakeDetector(config, dir.path()), nullptr);
  config.backend = "file";
  EXPECT_THROW(MakeDetector(config, dir.path()), InputError);
  test::WriteText(dir / "detections.txt", "1305031229.528748 0 0.9 1 2 3 4 person\n");
  const auto detector = MakeDetector(config, dir.path());
  ASSERT_NE(detector, nullptr);
  EXPECT_EQ(detector->Detect(cv::Mat(), kT0).size(), 1u);
  config.detections_file = (dir / "other.txt").string();
  EXPECT_THROW(MakeDetector(config, dir.path()), InputError);
}

// The ground truth `sgslam synth` writes replays frame by frame.
TEST(FileDetector, ReplaysASyntheticSequence) {
  test::TempDir dir;
  synth::SynthOptions options;
  options.frames = 4;
  synth::GenerateSequence(options, dir.path());
  const auto expected = ReadDetectionsFile(dir / "detections.txt");
  ASSERT_FALSE(expected.empty());
  FileDetector detector(dir / "detections.txt");
  for (const auto& [t, detections] : expected) {
    ExpectSame(detector.Detect(cv::Mat(), t), detections);
    ExpectSame(detector.Detect(cv::Mat(), t + 400'000), detections);  // rounding of a 6-decimal reader
  }
}

}  // namespace
}  // namespace sgslam
