// The OctoMap on request (SemanticMapper::RequestOctoMap; `sgslam run` on SIGUSR1):
// the live map so far is written to the file asked for, atomically, by the thread
// that owns it, in sequential and in parallel mode, and reloads with OctoMap's
// reader. Keyframes of a wall at 2 m, 5 mm apart.
#include <gtest/gtest.h>

#include <octomap/OcTree.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>
#include <shared_mutex>

#include "sgslam/map/features.h"
#include "sgslam/map/keyframe.h"
#include "sgslam/map/map.h"
#include "sgslam/semantic/semantic_mapper.h"
#include "semantic/semantic_scenes.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

void SubmitWall(SemanticMapper& mapper, Map& map, const Config& config, int from, int to) {
  const auto camera = std::make_shared<Camera>(config.camera);
  const auto scale = std::make_shared<ScaleLevels>(features::MakeScaleLevels(1.2, 8));
  const cv::Mat bgr(480, 640, CV_8UC3, cv::Scalar(90, 120, 150));
  const cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(2 * 5000));
  for (int k = from; k < to; ++k) {
    auto f = MakeFeatures({}, cv::Mat(0, 32, CV_8U), depth, camera, scale, {}, {});
    const SE3 T_c_w(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.005 * k, 0, 0));
    auto kf = std::make_shared<KeyFrame>(map.NewKeyFrameId(), static_cast<std::uint64_t>(k), 0, f, T_c_w);
    map.AddKeyFrame(kf);
    mapper.Submit({kf, bgr, depth});
  }
}

// -1: the file does not read.
long OccupiedLeaves(const std::filesystem::path& bt) {
  octomap::OcTree tree(0.1);
  if (!tree.readBinary(bt.string())) return -1;
  long n = 0;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) n += tree.isNodeOccupied(*it);
  return n;
}

Config WallConfig() {
  Config config;
  config.camera = test::PinholeCamera();
  config.semantic.filters.box_window = false;  // keyframes are processed as they come
  return config;
}

TEST(OctoMapRequest, SequentialWritesTheMapSoFarAtOnce) {
  const test::TempDir dir;
  const Config config = WallConfig();
  Map map;
  SemanticMapper mapper(config.semantic, std::make_shared<Camera>(config.camera), ClassTable(config.detector), map, /*sequential=*/true);
  mapper.RequestOctoMap(dir.path() / "empty.bt");  // before the first keyframe: an empty map, still a valid file
  EXPECT_EQ(OccupiedLeaves(dir.path() / "empty.bt"), 0);
  SubmitWall(mapper, map, config, 0, 3);
  mapper.RequestOctoMap(dir.path() / "so_far.bt");
  ASSERT_TRUE(std::filesystem::exists(dir.path() / "so_far.bt"));
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "so_far.bt.tmp"));
  EXPECT_GT(OccupiedLeaves(dir.path() / "so_far.bt"), 1000);  // a 2 m wall seen 4.6 x 3.5 m wide at 3 cm
  EXPECT_EQ(mapper.octomaps_written(), 2u);
  mapper.Finish();
}

TEST(OctoMapRequest, ParallelTheSemanticThreadWritesIt) {
  const test::TempDir dir;
  const Config config = WallConfig();
  Map map;
  SemanticMapper mapper(config.semantic, std::make_shared<Camera>(config.camera), ClassTable(config.detector), map, /*sequential=*/false);
  SubmitWall(mapper, map, config, 0, 3);
  mapper.RequestOctoMap(dir.path() / "so_far.bt");
  SubmitWall(mapper, map, config, 3, 5);
  mapper.Finish();  // a request still pending is served before the thread ends
  EXPECT_EQ(mapper.octomaps_written(), 1u);
  // The thread may serve it before it took any keyframe, or after one, two or three
  // of them (the request came before the others, and the thread serves it before
  // the next keyframe it takes): the map of the first k keyframes, k <= 3, as a
  // sequential mapper writes it.
  std::vector<long> first_k;
  {
    Map alone;
    SemanticMapper sequential(config.semantic, std::make_shared<Camera>(config.camera), ClassTable(config.detector), alone,
                              /*sequential=*/true);
    for (int k = 0; k <= 3; ++k) {
      if (k > 0) SubmitWall(sequential, alone, config, k - 1, k);
      const std::filesystem::path bt = dir.path() / ("first_" + std::to_string(k) + ".bt");
      sequential.RequestOctoMap(bt);
      first_k.push_back(OccupiedLeaves(bt));
    }
    sequential.Finish();
  }
  const long so_far = OccupiedLeaves(dir.path() / "so_far.bt");
  EXPECT_NE(so_far, -1) << "so_far.bt does not read";
  EXPECT_NE(std::find(first_k.begin(), first_k.end(), so_far), first_k.end())
      << so_far << " occupied leaves; the first 0..3 keyframes give " << ::testing::PrintToString(first_k);
  // After Finish() the caller's thread writes it, with every keyframe in.
  mapper.RequestOctoMap(dir.path() / "after.bt");
  EXPECT_EQ(mapper.octomaps_written(), 2u);
  EXPECT_GT(OccupiedLeaves(dir.path() / "after.bt"), 1000);
}

TEST(OctoMapRequest, AnUnwritablePathIsLoggedNotThrown) {
  const Config config = WallConfig();
  Map map;
  SemanticMapper mapper(config.semantic, std::make_shared<Camera>(config.camera), ClassTable(config.detector), map, /*sequential=*/true);
  SubmitWall(mapper, map, config, 0, 1);
  const test::TempDir dir;
  test::WriteText(dir / "a_file", "x");  // no folder can be made under a file
  EXPECT_NO_THROW(mapper.RequestOctoMap(dir / "a_file" / "so_far.bt"));
  EXPECT_EQ(mapper.octomaps_written(), 0u);
}

}  // namespace
}  // namespace sgslam
