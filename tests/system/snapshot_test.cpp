// The snapshot interface an observer (a viewer, a ROS node) reads while the system
// runs in parallel: another thread polls it throughout, and what it finally holds
// agrees with the system's own results.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <thread>

#include "sgslam/detection/detector.h"
#include "sgslam/io/frame_stream.h"
#include "sgslam/synth/writer.h"
#include "sgslam/system/run_config.h"
#include "sgslam/system/slam_system.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;

TEST(Snapshots, AnObserverReadsTheRunningSystem) {
  test::TempDir tmp;
  synth::SynthOptions o;
  o.preset = "objects";  // static furniture with ground-truth boxes: objects to publish
  o.frames = 90;
  o.seed = 1;
  synth::GenerateSequence(o, tmp / "seq");
  const RunConfig rc = ResolveRunConfig(std::nullopt, tmp / "seq");
  const TumDataset dataset(tmp / "seq", rc.config.dataset);
  SlamSystem system(rc.config, /*sequential=*/false, MakeDetector(rc.config.detector, tmp / "seq"));
  EXPECT_EQ(system.LatestFrame(), nullptr);
  system.EnableSnapshots();

  std::atomic<bool> done{false};
  std::size_t polls = 0, last_index = 0;
  bool ordered = true;
  std::thread observer([&] {  // what a viewer does, as often as it can
    while (!done) {
      if (const auto frame = system.LatestFrame()) {
        ordered = ordered && frame->index >= last_index && frame->labels.size() == frame->keypoints.size();
        last_index = frame->index;
      }
      const MapSnapshot map = system.SnapshotMap();
      ordered = ordered && std::all_of(map.cloud.begin(), map.cloud.end(), [](const CloudPiece& c) { return c.points_c; });
      ++polls;
    }
  });
  FrameStream stream(dataset, rc.config.camera, 2);
  FrameReport last;
  while (auto frame = stream.Next()) last = system.Process(*frame);
  system.Finish();
  done = true;
  observer.join();
  EXPECT_GT(polls, 0u);
  EXPECT_TRUE(ordered);

  const auto frame = system.LatestFrame();
  ASSERT_NE(frame, nullptr);
  EXPECT_EQ(frame->index, last.index);
  EXPECT_EQ(frame->state, TrackState::kOk);
  ASSERT_TRUE(frame->T_w_c);
  EXPECT_EQ(frame->keypoints.size(), static_cast<std::size_t>(last.features));
  const auto rejected = std::count(frame->labels.begin(), frame->labels.end(), FrameSnapshot::kRejected);
  EXPECT_EQ(rejected, last.features - last.kept);
  EXPECT_FALSE(frame->bgr.empty());

  const MapSnapshot map = system.SnapshotMap();
  EXPECT_EQ(map.keyframes.size(), system.NumKeyFrames());
  EXPECT_EQ(map.points.size(), system.MapPointPositions().size());
  ASSERT_FALSE(map.cloud.empty());
  std::size_t cloud_points = 0;
  for (const CloudPiece& c : map.cloud) cloud_points += c.points_c->size();
  EXPECT_GT(cloud_points, 1000u);
  EXPECT_FALSE(map.objects.empty()) << "the furniture seen so far";
  // The OctoMap's occupied cells: a few centimetres each, near the cloud's points.
  ASSERT_TRUE(map.cells);
  ASSERT_GT(map.cells->size(), 100u);
  for (const Eigen::Vector4f& c : *map.cells) {
    ASSERT_GT(c.w(), 0.f);
    ASSERT_LT(c.w(), 0.5f);
  }
  EXPECT_EQ(system.SnapshotMap().cells, map.cells) << "unchanged until the next keyframe: the same copy";
}

TEST(Snapshots, OffByDefault) {
  test::TempDir tmp;
  synth::SynthOptions o;
  o.preset = "static";
  o.frames = 5;
  synth::GenerateSequence(o, tmp / "seq");
  const RunConfig rc = ResolveRunConfig(std::nullopt, tmp / "seq");
  const TumDataset dataset(tmp / "seq", rc.config.dataset);
  SlamSystem system(rc.config, /*sequential=*/true);
  FrameStream stream(dataset, rc.config.camera, 2);
  while (auto frame = stream.Next()) system.Process(*frame);
  system.Finish();
  EXPECT_EQ(system.LatestFrame(), nullptr);
  EXPECT_TRUE(system.SnapshotMap().cloud.empty());
}

}  // namespace
}  // namespace sgslam
