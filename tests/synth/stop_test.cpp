// synth stopped part-way (sgslam synth on Ctrl-C or SIGTERM): the frames rendered
// so far are kept and listed, so the folder is a usable, shorter sequence.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "sgslam/io/tum_dataset.h"
#include "sgslam/synth/writer.h"
#include "support/test_support.h"

namespace sgslam::synth {
namespace {

namespace fs = std::filesystem;

std::size_t CountFiles(const fs::path& dir) {
  std::size_t n = 0;
  std::error_code ec;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) ++n;
  return n;
}

TEST(SynthStop, TheFramesRenderedSoFarAreListed) {
  const test::TempDir dir;
  std::atomic<bool> stop{false};
  std::thread stopper([&] {  // stops once a few frames are on disk
    while (CountFiles(dir / "seq" / "mask") < 6) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    stop = true;
  });
  SynthOptions o;
  o.preset = "static";
  o.frames = 300;
  o.stop = &stop;
  const SynthSummary s = GenerateSequence(o, dir / "seq");
  stopper.join();
  EXPECT_TRUE(s.stopped);
  EXPECT_GE(s.frames, 5);
  EXPECT_LT(s.frames, 300);
  // A sequence sgslam reads: every listed frame is there, the ground truth too.
  const TumDataset dataset(dir / "seq", DatasetConfig{});
  EXPECT_EQ(dataset.size(), static_cast<std::size_t>(s.frames));
  std::ifstream gt(dir / "seq" / "groundtruth.txt");
  std::string line;
  int poses = 0;
  while (std::getline(gt, line)) poses += !line.empty() && line[0] != '#';
  EXPECT_EQ(poses, s.frames);
}

TEST(SynthStop, AStopBeforeTheFirstFrameLeavesEmptyLists) {
  const test::TempDir dir;
  const std::atomic<bool> stop{true};
  SynthOptions o;
  o.preset = "static";
  o.frames = 10;
  o.stop = &stop;
  const SynthSummary s = GenerateSequence(o, dir / "seq");
  EXPECT_TRUE(s.stopped);
  EXPECT_EQ(s.frames, 0);
  EXPECT_TRUE(fs::exists(dir / "seq" / "rgb.txt"));
}

}  // namespace
}  // namespace sgslam::synth
