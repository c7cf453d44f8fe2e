// Localisation only (SlamSystem::SetLocalizationOnly): a map is made from the
// first part of a sequence, then the rest is tracked in it. No keyframe or map
// point may be added and the map must not change, nearly every frame must be
// localised, and their poses must agree with the ground truth at the alignment
// fitted on the frames that made the map. Synthetic: the `static` room; real: TUM
// fr1_rpy's first 350 frames, then the rest (skipped without ../shared).
#include <gtest/gtest.h>

#include <filesystem>

#include "sgslam/eval/ate.h"
#include "sgslam/io/frame_stream.h"
#include "sgslam/synth/writer.h"
#include "sgslam/system/run_config.h"
#include "sgslam/system/slam_system.h"
#include "support/shared_folder.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;

struct MapState {
  std::vector<Eigen::Vector3d> points;
  Trajectory keyframes;
};

MapState StateOf(const SlamSystem& system) { return {system.MapPointPositions(), system.KeyFrameTrajectory()}; }

struct Outcome {
  Trajectory mapped;               // the frames that made the map
  Trajectory localised;            // the frames after the switch that were localised
  std::size_t frames = 0;          // after the switch
  std::size_t keyframes_made = 0;  // after the switch, by the frame reports
  MapState after_first, at_end;    // the map after the first localised frame, and at the end
};

// The first map_frames frames of dir map, the others are localised in that map.
Outcome MapThenLocalise(const fs::path& dir, std::size_t map_frames) {
  RunConfig rc = ResolveRunConfig(std::nullopt, dir);
  rc.config.dynamic.mode = "none";
  rc.config.semantic.enabled = false;
  const TumDataset dataset(dir, rc.config.dataset);
  SlamSystem system(rc.config, /*sequential=*/true);
  FrameStream stream(dataset, rc.config.camera, 2);
  Outcome out;
  std::size_t mapped = 0;
  while (auto frame = stream.Next()) {
    if (frame->index == map_frames) {
      mapped = system.FrameTrajectory().size();
      system.SetLocalizationOnly(true);
    }
    const FrameReport r = system.Process(*frame);
    if (frame->index < map_frames) continue;
    ++out.frames;
    out.keyframes_made += r.keyframe ? 1 : 0;
    // The keyframe made just before the switch is mapped with this frame (it waited
    // for it: TrackResult::keyframe_held).
    if (frame->index == map_frames) out.after_first = StateOf(system);
  }
  system.Finish();
  out.at_end = StateOf(system);
  const Trajectory all = system.FrameTrajectory();
  out.mapped.assign(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(mapped));
  out.localised.assign(all.begin() + static_cast<std::ptrdiff_t>(mapped), all.end());
  return out;
}

// ATE RMSE of the localised frames at the alignment of the mapping part.
double LocalisedAte(const fs::path& dir, const Outcome& o) {
  const Trajectory gt = ReadTumTrajectory(dir / "groundtruth.txt");
  const eval::AteResult map_fit = eval::ComputeAte(gt, o.mapped, FromSeconds(0.02));
  return eval::ComputeAteAt(gt, o.localised, map_fit.T_gt_est, FromSeconds(0.02)).stats.rmse;
}

void ExpectMapUnchanged(const Outcome& o) {
  EXPECT_EQ(o.keyframes_made, 0u);
  EXPECT_EQ(o.after_first.points, o.at_end.points);
  ASSERT_EQ(o.after_first.keyframes.size(), o.at_end.keyframes.size());
  for (std::size_t i = 0; i < o.at_end.keyframes.size(); ++i) {
    EXPECT_EQ(o.after_first.keyframes[i].T_w_c.translation(), o.at_end.keyframes[i].T_w_c.translation()) << i;
  }
}

// The `static` room, rendered once for both tests (test::SharedSequence).
fs::path Room() {
  synth::SynthOptions o;
  o.preset = "static";
  o.frames = 240;
  o.seed = 3;
  return test::SharedSequence(o);
}

TEST(LocalisationSynthetic, RoomLocalisedInTheMapOfItsFirstPart) {
  const Outcome out = MapThenLocalise(Room(), 150);
  ExpectMapUnchanged(out);
  EXPECT_GE(out.localised.size(), 0.95 * static_cast<double>(out.frames));
  EXPECT_LT(LocalisedAte(Room(), out), 0.01);
}

// A system in localisation mode from its first frame expects a map made elsewhere:
// without one it starts none.
TEST(LocalisationSynthetic, NoMapIsStartedInLocalisationMode) {
  const Outcome out = MapThenLocalise(Room(), 0);
  EXPECT_EQ(out.keyframes_made, 0u);
  EXPECT_TRUE(out.localised.empty());
  EXPECT_TRUE(out.at_end.keyframes.empty());
  EXPECT_TRUE(out.at_end.points.empty());
}

TEST(Localisation, TumFr1RpyLocalisedInTheMapOfItsFirst350Frames) {
  SGSLAM_REQUIRE_SHARED(dir, "data/tum_fr1_rpy");
  const Outcome out = MapThenLocalise(dir, 350);
  ExpectMapUnchanged(out);
  EXPECT_GE(out.localised.size(), 0.95 * static_cast<double>(out.frames));
  EXPECT_LE(LocalisedAte(dir, out), 0.02);
}

}  // namespace
}  // namespace sgslam
