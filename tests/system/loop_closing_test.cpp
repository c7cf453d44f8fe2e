// Loop closing end to end on the synthetic `loop` preset (a hall walked round
// twice with a Kinect-like sensor and a rolling shutter: odometry drifts by tens of
// centimetres a lap) and the `repeat` preset (a corridor of identical modules: places
// that look and fit alike but are metres apart). The loop must be found soon after
// the camera is back and correct the trajectory, sequentially and with the threads
// running; the look-alike places must never be taken for a loop.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>

#include "sgslam/eval/ate.h"
#include "sgslam/io/frame_stream.h"
#include "sgslam/synth/writer.h"
#include "sgslam/system/run_config.h"
#include "sgslam/system/slam_system.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  Trajectory trajectory;
  std::vector<LoopReport> loops;
  std::vector<Timestamp> keyframe_times;  // frames a keyframe was made at
  std::size_t tracked = 0, frames = 0;
  std::vector<std::string> map_problems;
};

Outcome RunOn(const fs::path& dir, bool loop_closing, bool sequential = true) {
  RunConfig rc = ResolveRunConfig(std::nullopt, dir);
  rc.config.dynamic.mode = "none";
  rc.config.semantic.enabled = false;
  rc.config.loop.enabled = loop_closing;
  const TumDataset dataset(dir, rc.config.dataset);
  SlamSystem system(rc.config, sequential);
  FrameStream stream(dataset, rc.config.camera, 2);
  Outcome out;
  while (auto frame = stream.Next()) {
    const FrameReport r = system.Process(*frame);
    ++out.frames;
    out.tracked += r.state == TrackState::kOk;
    if (r.keyframe) out.keyframe_times.push_back(r.t);
  }
  system.Finish();
  out.trajectory = system.FrameTrajectory();
  for (const auto& l : system.loop_reports()) {
    if (l.closed || l.implausible > 0) out.loops.push_back(l);
  }
  out.map_problems = system.CheckMap();
  return out;
}

double Ate(const fs::path& dir, const Trajectory& t) {
  return eval::ComputeAte(ReadTumTrajectory(dir / "groundtruth.txt"), t, FromSeconds(0.02)).stats.rmse;
}

// The first time the camera is back within 0.5 m and 30 degrees of where it was at
// least 10 s before (ground truth).
Timestamp FirstRevisit(const Trajectory& gt) {
  for (std::size_t i = 0; i < gt.size(); i += 3) {
    const Eigen::Vector3d axis = gt[i].T_w_c.rotation().col(2);
    for (std::size_t j = 0; j < i && ToSeconds(gt[i].t - gt[j].t) >= 10; j += 3) {
      if ((gt[i].T_w_c.translation() - gt[j].T_w_c.translation()).norm() < 0.5 &&
          axis.dot(gt[j].T_w_c.rotation().col(2)) > std::cos(30 * M_PI / 180)) {
        return gt[i].t;
      }
    }
  }
  return 0;
}

// A preset's sequence, made on first use (CTest runs each test in a process of its
// own: each makes only what it needs).
fs::path Sequence(const std::string& preset, int frames) {
  static test::TempDir dir;
  const fs::path seq = dir / preset;
  if (!fs::exists(seq / "rgb.txt")) {
    synth::SynthOptions o;
    o.preset = preset;
    o.frames = frames;
    synth::GenerateSequence(o, seq);
  }
  return seq;
}

// The first lap and the loop found on the second.
constexpr int kLoopFrames = 1100;

TEST(LoopClosing, TheLoopIsFoundSoonAndCorrectsTheDrift) {
  const fs::path seq = Sequence("loop", kLoopFrames);
  const Outcome with = RunOn(seq, true);
  const Outcome without = RunOn(seq, false);
  EXPECT_EQ(with.tracked, with.frames);
  EXPECT_TRUE(with.map_problems.empty()) << with.map_problems.front();
  ASSERT_FALSE(with.loops.empty());
  const LoopReport& first = with.loops.front();
  EXPECT_TRUE(first.closed);
  EXPECT_EQ(first.implausible, 0);
  // Found within 10 keyframes of the camera's return.
  const Timestamp revisit = FirstRevisit(ReadTumTrajectory(seq / "groundtruth.txt"));
  ASSERT_GT(revisit, 0);
  const auto made = std::count_if(with.keyframe_times.begin(), with.keyframe_times.end(),
                                  [&](Timestamp t) { return t >= revisit && t <= first.t; });
  EXPECT_LE(made, 10);
  const double ate_with = Ate(seq, with.trajectory), ate_without = Ate(seq, without.trajectory);
  EXPECT_LT(ate_with, 0.02);
  EXPECT_LT(ate_with, ate_without / 3) << ate_with << " against " << ate_without;
  // With the loop and global-BA threads running (here, not a second process: the
  // sequence is made once). Where keyframes are made then depends on the threads'
  // timing: on a loaded machine local mapping falls behind, the odometry drifts more
  // before the loop (one CI run found it at frame 973 with a 0.66 m correction,
  // against 0.088 m at frame 1043 sequentially) and the run ended at 0.034-0.036 m,
  // where a quiet machine gives under 0.02. The sequential run without the loop is
  // no baseline for that drift, so the bound is the loaded figure with a margin: the
  // loop found, the map whole and the trajectory within 5 cm.
  const Outcome parallel = RunOn(seq, true, /*sequential=*/false);
  EXPECT_TRUE(std::any_of(parallel.loops.begin(), parallel.loops.end(), [](const LoopReport& l) { return l.closed; }));
  EXPECT_TRUE(parallel.map_problems.empty()) << parallel.map_problems.front();
  EXPECT_LT(Ate(seq, parallel.trajectory), 0.05) << "without the loop, sequentially: " << ate_without;
}

TEST(LoopClosing, LookAlikePlacesAreNeverTakenForALoop) {
  const fs::path seq = Sequence("repeat", 450);
  const Outcome out = RunOn(seq, true);
  int refused = 0;
  for (const LoopReport& l : out.loops) {
    EXPECT_FALSE(l.closed) << "frame " << l.frame << " with " << l.loop_frame;
    refused += l.implausible;
  }
  EXPECT_GT(refused, 0) << "no look-alike place passed verification: the preset no longer tests the drift rule";
  EXPECT_LT(Ate(seq, out.trajectory), 0.03);
}

}  // namespace
}  // namespace sgslam
