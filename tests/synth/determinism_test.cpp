#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "sgslam/synth/sequence.h"
#include "sgslam/synth/writer.h"
#include "support/test_support.h"

namespace sgslam::synth {
namespace {

namespace fs = std::filesystem;

bool SameBytes(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && a.isContinuous() && b.isContinuous() &&
         std::equal(a.datastart, a.dataend, b.datastart);
}

std::map<std::string, std::string> ReadTree(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (!e.is_regular_file()) continue;
    std::ifstream in(e.path(), std::ios::binary);
    files[fs::relative(e.path(), root).string()] = std::string(std::istreambuf_iterator<char>(in), {});
  }
  return files;
}

TEST(SynthDeterminism, SameSeedRendersSameBytesOtherSeedDiffers) {
  const SynthSequence a("walkers", 1, 30), b("walkers", 1, 30), c("walkers", 2, 30);
  const RenderedFrame fa = a.Render(17), fb = b.Render(17), fc = c.Render(17);
  EXPECT_TRUE(SameBytes(fa.bgr, fb.bgr));
  EXPECT_TRUE(SameBytes(fa.depth, fb.depth));
  EXPECT_TRUE(SameBytes(fa.object_id, fb.object_id));
  EXPECT_FALSE(SameBytes(fa.bgr, fc.bgr));
  EXPECT_FALSE(SameBytes(fa.depth, fc.depth));
  EXPECT_NE(a.scene().room_size, c.scene().room_size);
  EXPECT_GT((a.CameraPose(0).translation() - c.CameraPose(0).translation()).norm(), 1e-3);
  EXPECT_GT((a.ObjectPose(1, 10).translation() - c.ObjectPose(1, 10).translation()).norm(), 1e-3);
}

TEST(SynthDeterminism, FilesAreByteIdenticalWhateverTheThreadCount) {
  test::TempDir dir;
  SynthOptions o;
  o.frames = 5;
  o.threads = 2;
  GenerateSequence(o, dir / "a");
  o.threads = 1;
  GenerateSequence(o, dir / "b");
  o.seed = 7;
  o.threads = 2;
  GenerateSequence(o, dir / "c");
  const auto a = ReadTree(dir / "a"), b = ReadTree(dir / "b"), c = ReadTree(dir / "c");
  ASSERT_EQ(a.size(), 3u * 5u + 9u);  // 3 images a frame + 9 list/ground-truth files (movers.txt)
  EXPECT_TRUE(a == b);
  ASSERT_EQ(a.size(), c.size());
  int differing = 0;
  for (const auto& [name, bytes] : a) differing += c.at(name) != bytes;
  EXPECT_GE(differing, 2 * 5 + 2);  // every RGB and depth image, the ground truth, the detections
  EXPECT_NE(a.at("groundtruth.txt"), c.at("groundtruth.txt"));
}

}  // namespace
}  // namespace sgslam::synth
