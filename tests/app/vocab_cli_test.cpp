// `sgslam vocab` as a user meets it: train from a folder of images, inspect the
// file, and clear errors for broken files and bad options.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sgslam/vocab/vocabulary.h"
#include "support/test_support.h"
#include "support/tiny_dataset.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;
using test::RunSgslam;
using test::TempDir;

// n textured 320x240 images (random blocks: ORB finds corners on them).
void WriteImages(const fs::path& dir, int n) {
  fs::create_directories(dir);
  cv::RNG rng(5);
  for (int i = 0; i < n; ++i) {
    cv::Mat img(240, 320, CV_8UC3);
    rng.fill(img, cv::RNG::UNIFORM, 0, 255);
    cv::Mat small(24, 32, CV_8UC3);
    rng.fill(small, cv::RNG::UNIFORM, 0, 255);
    cv::resize(small, img, img.size(), 0, 0, cv::INTER_NEAREST);
    cv::imwrite((dir / ("img" + std::to_string(i) + ".png")).string(), img);
  }
}

TEST(VocabCommand, TrainsFromAFolderAndTheFileLoads) {
  TempDir tmp;
  WriteImages(tmp / "images", 6);
  const auto r = RunSgslam({"vocab", "train", "--images", (tmp / "images").string(), "--out",
                            (tmp / "v.vocab").string(), "--k", "4", "--levels", "3"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("from 6 images"), std::string::npos) << r.output;
  const vocab::Vocabulary v = vocab::Vocabulary::Load(tmp / "v.vocab");
  EXPECT_EQ(v.branching(), 4);
  EXPECT_EQ(v.levels(), 3);
  EXPECT_EQ(v.training_images(), 6U);
  const auto info = RunSgslam({"vocab", "info", (tmp / "v.vocab").string()});
  EXPECT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find(v.checksum()), std::string::npos) << info.output;
}

TEST(VocabCommand, BadInputIsNamed) {
  TempDir tmp;
  fs::create_directories(tmp / "empty");
  auto r = RunSgslam({"vocab", "train", "--images", (tmp / "empty").string(), "--out", (tmp / "v.vocab").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("no rgb.txt and no images"), std::string::npos) << r.output;
  r = RunSgslam({"vocab", "train", "--images", (tmp / "nothing").string(), "--out", (tmp / "v.vocab").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("no such file or folder"), std::string::npos) << r.output;
  WriteImages(tmp / "images", 2);
  r = RunSgslam({"vocab", "train", "--images", (tmp / "images").string(), "--out", (tmp / "v.vocab").string(), "--k",
                 "1"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("--k"), std::string::npos) << r.output;
  std::ofstream(tmp / "broken.vocab") << "SGVOCAB";
  r = RunSgslam({"vocab", "info", (tmp / "broken.vocab").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("broken.vocab"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(tmp / "v.vocab"));
}

TEST(VocabCommand, ARunWithABrokenVocabularyStopsNamingIt) {
  TempDir tmp;
  std::ofstream(tmp / "broken.vocab") << "not a vocabulary";
  std::ofstream(tmp / "c.yaml") << "loop:\n  vocabulary: " << (tmp / "broken.vocab").string() << "\n";
  test::WriteTinyDataset(tmp / "seq", 2);
  const auto r = RunSgslam({"run", "--dataset", (tmp / "seq").string(), "--config", (tmp / "c.yaml").string(),
                            "--out", (tmp / "out").string(), "--mode", "none"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("broken.vocab"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace sgslam
