// Map reuse end to end on a synthetic sequence with exact ground truth: a map saved
// at the end of one run is where the next run starts (the first frame relocalised
// in it, poses in its frame), extending it or only localising in it; maps saved
// while the threads run are whole and load again to the same content.
#include <gtest/gtest.h>

#include <filesystem>

#include "sgslam/eval/ate.h"
#include "sgslam/io/frame_stream.h"
#include "sgslam/mapfile/map_file.h"
#include "sgslam/synth/writer.h"
#include "sgslam/system/run_config.h"
#include "sgslam/system/slam_system.h"
#include "support/shared_folder.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;

// Rendered once for both tests (test::SharedSequence).
fs::path Walkers() {
  synth::SynthOptions o;
  o.preset = "walkers";
  o.frames = 150;
  return test::SharedSequence(o);
}

RunConfig Config(const fs::path& seq) {
  RunConfig rc = ResolveRunConfig(std::nullopt, seq);
  rc.config.dynamic.mode = "geometric";  // no detector needed; the movers are still rejected
  return rc;
}

struct Outcome {
  Trajectory trajectory;
  std::vector<TrackState> states;
  std::size_t keyframes = 0, saves_requested = 0, saves = 0;
};

// Runs seq through a system, from `load` when given, saving to `save` at the end
// (and every `save_every` frames while running, to numbered files).
Outcome RunSequence(const fs::path& seq, bool sequential, const fs::path& load, const fs::path& save, int save_every = 0,
                    bool localize = false) {
  const RunConfig rc = Config(seq);
  const TumDataset dataset(seq, rc.config.dataset);
  SlamSystem system(rc.config, sequential);
  if (!load.empty()) system.LoadMap(mapfile::ReadMapFile(load), load.string());
  system.SetLocalizationOnly(localize);
  FrameStream stream(dataset, rc.config.camera, 2);
  Outcome out;
  while (auto frame = stream.Next()) {
    out.states.push_back(system.Process(*frame).state);
    if (save_every > 0 && out.states.size() % save_every == 0) {
      const fs::path live = save.string() + "." + std::to_string(out.states.size());
      out.saves_requested += system.SaveMap(live);
    }
  }
  system.Finish();
  if (!save.empty()) {
    EXPECT_TRUE(system.SaveMap(save));
  }
  out.saves = system.maps_saved();
  out.trajectory = system.FrameTrajectory();
  out.keyframes = system.NumKeyFrames();
  return out;
}

// Where two maps differ, for a failure message ("" when they have the same content).
std::string FirstDifference(const mapfile::MapData& a, const mapfile::MapData& b) {
  if (a.next_keyframe_id != b.next_keyframe_id || a.next_point_id != b.next_point_id) return "id counters";
  if (a.next_frame_id != b.next_frame_id) return "next frame id";
  if (a.keyframes.size() != b.keyframes.size()) return "keyframe count";
  for (std::size_t i = 0; i < a.keyframes.size(); ++i) {
    if (!(a.keyframes[i] == b.keyframes[i])) return "keyframe " + std::to_string(a.keyframes[i].id);
  }
  if (!(a.points == b.points)) return "map points";
  if (!(a.semantic == b.semantic)) return "semantic layer";
  return mapfile::SameContent(a, b) ? "" : "settings";
}

TEST(MapReuse, TheNextRunStartsInTheSavedMap) {
  const test::TempDir dir;
  const fs::path seq = Walkers();
  const Outcome first = RunSequence(seq, true, {}, dir / "walkers.map");
  const Outcome again = RunSequence(seq, true, dir / "walkers.map", {});
  EXPECT_EQ(again.states.front(), TrackState::kOk) << "the first frame is relocalised in the map";
  const auto tracked = std::count(again.states.begin(), again.states.end(), TrackState::kOk);
  EXPECT_GE(tracked, static_cast<long>(again.states.size() * 95 / 100));
  // Poses in the map's frame: aligned as the first run was, not fitted again.
  const Trajectory gt = ReadTumTrajectory(seq / "groundtruth.txt");
  const SE3 T_gt_map = eval::ComputeAte(gt, first.trajectory, FromSeconds(0.02)).T_gt_est;
  const double ate = eval::ComputeAteAt(gt, again.trajectory, T_gt_map, FromSeconds(0.02)).stats.rmse;
  EXPECT_LT(ate, 0.02);
  // The same places: the map hardly grows.
  EXPECT_LE(again.keyframes, first.keyframes + 3);
  // Localising only: the same, and nothing added.
  const Outcome localised = RunSequence(seq, true, dir / "walkers.map", {}, 0, /*localize=*/true);
  EXPECT_EQ(localised.states.front(), TrackState::kOk);
  EXPECT_GE(std::count(localised.states.begin(), localised.states.end(), TrackState::kOk),
            static_cast<long>(localised.states.size() * 95 / 100));
  EXPECT_LT(eval::ComputeAteAt(gt, localised.trajectory, T_gt_map, FromSeconds(0.02)).stats.rmse, 0.02);
  EXPECT_EQ(localised.keyframes, first.keyframes);
}

// Run under TSan in CI's sanitizer job: the copy runs on the semantic thread, the
// write on a thread of its own, while tracking and local mapping go on.
TEST(MapReuse, MapsSavedWhileRunningAreWhole) {
  const test::TempDir dir;
  const fs::path seq = Walkers();
  const Outcome run = RunSequence(seq, /*sequential=*/false, {}, dir / "live.map", /*save_every=*/25);
  // A request while the last save is being written is refused: how many are taken
  // depends on the machine's speed.
  EXPECT_GE(run.saves_requested, 1u);
  EXPECT_EQ(run.saves, run.saves_requested + 1);
  for (int n = 25; n <= 150; n += 25) {
    const fs::path live = dir / ("live.map." + std::to_string(n));
    if (!fs::exists(live)) continue;  // refused: the previous save was still being written
    const mapfile::MapData d = mapfile::ReadMapFile(live);  // whole: its checks pass
    // A map copied mid-run (keyframes waiting for local mapping left out) loads and
    // saves again to the same content.
    const RunConfig rc = Config(seq);
    SlamSystem loaded(rc.config, /*sequential=*/true);
    loaded.LoadMap(d, live.string());
    ASSERT_TRUE(loaded.SaveMap(live.string() + ".again"));
    EXPECT_EQ(FirstDifference(d, mapfile::ReadMapFile(live.string() + ".again")), "") << live;
  }
  EXPECT_GT(mapfile::ReadMapFile(dir / "live.map").keyframes.size(), 5u);
}

}  // namespace
}  // namespace sgslam
