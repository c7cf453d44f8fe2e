// The whole pipeline, short: 60 frames of the synthetic `walkers` sequence (people
// walking through a room, their ground-truth boxes as the detector) in the default
// mode (sg), with the semantic map, sequentially and with its threads. The fast
// test set's end-to-end check (the long whole-system suites are labelled slow), and
// the test of the sequential pipeline's determinism: a second run gives the same
// trajectory, bit for bit, and a map and cloud of the same size.
#include <gtest/gtest.h>

#include <filesystem>

#include "sgslam/detection/detector.h"
#include "sgslam/eval/ate.h"
#include "sgslam/io/frame_stream.h"
#include "sgslam/synth/writer.h"
#include "sgslam/system/run_config.h"
#include "sgslam/system/slam_system.h"
#include "support/shared_folder.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  std::size_t frames = 0, tracked = 0, rejected = 0;
  Trajectory trajectory;
  std::size_t keyframes = 0, points = 0, cloud = 0;
  std::vector<std::string> map_problems;
};

Outcome RunOn(const fs::path& seq, bool sequential) {
  RunConfig rc = ResolveRunConfig(std::nullopt, seq);
  // The semantic thread at the others' priority: at the lowest (the default), a
  // test running beside it on two cores starves it and Finish() waits for it (the
  // parallel run took 56 s instead of 8).
  rc.config.semantic.low_priority = false;
  const TumDataset dataset(seq, rc.config.dataset);
  SlamSystem system(rc.config, sequential, MakeDetector(rc.config.detector, seq));
  FrameStream stream(dataset, rc.config.camera, 2);
  Outcome out;
  while (auto frame = stream.Next()) {
    const FrameReport r = system.Process(*frame);
    ++out.frames;
    out.tracked += r.state == TrackState::kOk;
    out.rejected += static_cast<std::size_t>(r.features - r.kept);
  }
  system.Finish();
  out.trajectory = system.FrameTrajectory();
  out.keyframes = system.NumKeyFrames();
  out.points = system.MapPointPositions().size();
  std::vector<Eigen::Vector3d> cloud;
  std::vector<Rgb> colours;
  std::vector<ObjectEstimate> objects;
  system.ExportSemantic(cloud, colours, objects);
  out.cloud = cloud.size();
  out.map_problems = system.CheckMap();
  return out;
}

// Rendered once for both tests (test::SharedSequence).
fs::path Walkers() {
  synth::SynthOptions o;
  o.preset = "walkers";
  o.frames = 60;
  return test::SharedSequence(o);
}

TEST(ShortRun, WalkersSequentialIsAccurateAndDeterministic) {
  const fs::path seq = Walkers();
  ASSERT_EQ(ResolveRunConfig(std::nullopt, seq).config.dynamic.mode, "sg") << "the default mode";

  const Outcome a = RunOn(seq, /*sequential=*/true);
  EXPECT_EQ(a.frames, 60u);
  EXPECT_EQ(a.tracked, a.frames);
  EXPECT_TRUE(a.map_problems.empty()) << a.map_problems.front();
  EXPECT_GT(a.keyframes, 3u);
  EXPECT_GT(a.rejected, 100u) << "the walkers' keypoints are rejected";
  EXPECT_GT(a.cloud, 10000u) << "a static cloud";
  const auto ate = eval::ComputeAte(ReadTumTrajectory(seq / "groundtruth.txt"), a.trajectory, FromSeconds(0.02));
  EXPECT_EQ(ate.stats.count, a.frames);
  EXPECT_LT(ate.stats.rmse, 0.01);  // 0.0035 m on 2026-12-06

  const Outcome b = RunOn(seq, /*sequential=*/true);
  EXPECT_EQ(b.keyframes, a.keyframes);
  EXPECT_EQ(b.points, a.points);
  EXPECT_EQ(b.cloud, a.cloud);
  ASSERT_EQ(a.trajectory.size(), b.trajectory.size());
  for (std::size_t i = 0; i < a.trajectory.size(); ++i) {
    EXPECT_EQ(a.trajectory[i].T_w_c.translation(), b.trajectory[i].T_w_c.translation()) << i;
    EXPECT_EQ(a.trajectory[i].T_w_c.quaternion().coeffs(), b.trajectory[i].T_w_c.quaternion().coeffs()) << i;
  }
}

// With the detection, local mapping, loop and semantic threads.
TEST(ShortRun, WalkersParallelIsAccurate) {
  const fs::path seq = Walkers();
  const Outcome a = RunOn(seq, /*sequential=*/false);
  EXPECT_EQ(a.frames, 60u);
  EXPECT_GE(a.tracked, a.frames - 1);
  EXPECT_TRUE(a.map_problems.empty()) << a.map_problems.front();
  EXPECT_GT(a.rejected, 100u) << "the walkers' keypoints are rejected";
  EXPECT_GT(a.cloud, 10000u) << "a static cloud";
  const auto ate = eval::ComputeAte(ReadTumTrajectory(seq / "groundtruth.txt"), a.trajectory, FromSeconds(0.02));
  EXPECT_LT(ate.stats.rmse, 0.015);  // 0.0034 m on 2026-12-06 (sgslam run)
}

}  // namespace
}  // namespace sgslam
