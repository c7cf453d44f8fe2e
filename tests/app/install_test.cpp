// `cmake --install` puts sgslam, its detector models and its camera configs under a
// prefix; the installed binary, run from another folder with no model option and
// no $SGSLAM_MODEL_DIR, finds both beside itself and runs the real detector.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "support/test_support.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;
using test::ShellQuote;

TEST(Install, InstalledBinaryFindsItsModelsAndConfigs) {
  test::TempDir tmp;
  const fs::path prefix = tmp / "prefix";
  const auto install = test::RunShell(ShellQuote(SGSLAM_CMAKE) + " --install " + ShellQuote(SGSLAM_BUILD_DIR) +
                                      " --prefix " + ShellQuote(prefix.string()));
  ASSERT_EQ(install.exit_code, 0) << install.output;
  const fs::path bin = prefix / "bin" / "sgslam";
  const fs::path models = prefix / "share" / "sgslam" / "models" / "yolo-fastest-1.1-coco";
  ASSERT_TRUE(fs::is_regular_file(bin));
  for (const char* f : {"yolo-fastest-1.1.cfg", "yolo-fastest-1.1.weights", "yolo-fastest-1.1-xl.weights",
                        "coco.names", "SHA256SUMS", "LICENSE.darknet-YOLO"}) {
    EXPECT_TRUE(fs::is_regular_file(models / f)) << f;
  }
  EXPECT_TRUE(fs::is_regular_file(prefix / "share" / "sgslam" / "configs" / "tum_fr3.yaml"));

  // From an unrelated working folder, with the environment variable unset: a
  // small synthetic sequence (640x480) under the shipped fr3 camera config, whose
  // detector is the default one (the network, not the sequence's file boxes).
  const fs::path work = tmp / "elsewhere";
  fs::create_directories(work);
  const std::string cd = "cd " + ShellQuote(work.string()) + " && env -u SGSLAM_MODEL_DIR " + ShellQuote(bin.string());
  const auto synth = test::RunShell(cd + " -q synth --preset walkers --frames 8 --out seq");
  ASSERT_EQ(synth.exit_code, 0) << synth.output;
  const auto run = test::RunShell(cd + " run --dataset seq --config tum_fr3 --mode sg --sequential --out out");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::ifstream stats_file(work / "out" / "stats.json");
  const auto stats = nlohmann::json::parse(stats_file);
  const std::string detector = stats["dynamic"]["detector"].get<std::string>();
  EXPECT_NE(detector.find((models / "yolo-fastest-1.1.cfg").string()), std::string::npos) << detector;
  EXPECT_EQ(stats["frames"].get<int>(), 8);
  std::ifstream used(work / "out" / "config_used.yaml");
  const std::string config((std::istreambuf_iterator<char>(used)), std::istreambuf_iterator<char>());
  EXPECT_NE(config.find("tum_fr3.yaml"), std::string::npos) << "the source line names the shipped file";
  EXPECT_NE(config.find("fx: 535.4"), std::string::npos) << config.substr(0, 400);
}

}  // namespace
}  // namespace sgslam
