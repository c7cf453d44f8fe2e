// End to end on synthetic sequences with exact ground truth: the whole system in
// sequential mode must track a static scene to within a centimetre. (That a
// sequential run gives the same trajectory bit for bit on every run is
// system/short_run_test.cpp's check.)
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <shared_mutex>

#include "sgslam/detection/detector.h"
#include "sgslam/eval/ate.h"
#include "sgslam/io/frame_stream.h"
#include "sgslam/map/map_check.h"
#include "sgslam/synth/writer.h"
#include "sgslam/system/run_config.h"
#include "sgslam/system/slam_system.h"
#include "support/shared_folder.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  Trajectory trajectory;
  Trajectory online;  // as tracking output it
  std::size_t frames = 0, tracked = 0;
  std::vector<std::string> map_problems;
  std::size_t keyframes = 0;
  std::size_t keyframes_made = 0;    // frames whose report says a keyframe was made
  std::size_t keyframes_mapped = 0;  // keyframes local mapping processed
  int last_map_keyframes = 0;        // the map's keyframes as the last frame's report gives them
  std::optional<MappingStats> final_ba;
};

// Person boxes over all but the top-left 120x90 px of the first n frames of dir,
// in a detections file at `file` (three boxes, each under the box area limit, R8).
void WriteCoveringBoxes(const fs::path& dir, std::size_t n, const fs::path& file) {
  std::ifstream rgb(dir / "rgb.txt");
  std::ofstream det(file);
  std::string line;
  for (std::size_t i = 0; i < n && std::getline(rgb, line);) {
    if (line.empty() || line[0] == '#') continue;
    const std::string t = line.substr(0, line.find(' '));
    det << t << " 0 0.9 120 0 640 240 person\n"
        << t << " 0 0.9 120 240 640 480 person\n"
        << t << " 0 0.9 0 90 120 480 person\n";
    ++i;
  }
}

// blank: frames [first, last) arrive black and without depth (a covered lens).
// covered: the first `covered` frames have person boxes over all but their
// top-left 120x90 px (mode semantic, no fallback), as a frame whose
// false-positive boxes cover nearly everything would be.
Outcome RunOn(const fs::path& dir, bool sequential, std::pair<std::size_t, std::size_t> blank = {0, 0},
              std::size_t covered = 0, std::vector<TrackState>* states = nullptr,
              const std::function<void(Config&)>& tweak = {}) {
  RunConfig rc = ResolveRunConfig(std::nullopt, dir);
  if (tweak) tweak(rc.config);
  std::unique_ptr<Detector> detector;
  test::TempDir boxes;
  if (covered > 0) {
    WriteCoveringBoxes(dir, covered, boxes / "covering.txt");
    rc.config.dynamic.mode = "semantic";
    rc.config.dynamic.refinements.fallback = false;
    rc.config.detector.backend = "file";
    rc.config.detector.detections_file = (boxes / "covering.txt").string();
    detector = MakeDetector(rc.config.detector, dir);
  }
  const TumDataset dataset(dir, rc.config.dataset);
  SlamSystem system(rc.config, sequential, std::move(detector));
  FrameStream stream(dataset, rc.config.camera, 2);
  Outcome out;
  while (auto frame = stream.Next()) {
    if (frame->index >= blank.first && frame->index < blank.second) {
      frame->bgr = cv::Mat::zeros(frame->bgr.size(), frame->bgr.type());
      frame->depth = cv::Mat::zeros(frame->depth.size(), frame->depth.type());
    }
    const FrameReport r = system.Process(*frame);
    if (states) states->push_back(r.state);
    ++out.frames;
    out.tracked += r.state == TrackState::kOk;
    out.keyframes_made += r.keyframe ? 1 : 0;
    out.last_map_keyframes = r.map_keyframes;
  }
  system.Finish();
  out.keyframes_mapped = system.mapping_stats().size();
  out.trajectory = system.FrameTrajectory();
  out.online = system.OnlineTrajectory();
  out.map_problems = system.CheckMap();
  out.keyframes = system.NumKeyFrames();
  out.final_ba = system.final_ba();
  return out;
}

// The sequences, rendered once for all the tests of this file (test::SharedSequence).
fs::path Static() {
  synth::SynthOptions o;
  o.preset = "static";
  o.frames = 150;
  o.seed = 3;
  return test::SharedSequence(o);
}

fs::path Walkers() {
  synth::SynthOptions o;
  o.preset = "walkers";
  o.frames = 80;  // without dynamic rejection nearly every frame is a keyframe: slow
  o.seed = 3;
  return test::SharedSequence(o);
}

fs::path Rolling() {
  synth::SynthOptions o;
  o.preset = "rpy";  // turns up to ~1.3 rad/s, like fr1_rpy
  o.frames = 120;
  o.seed = 3;
  o.readout = 0.03;
  return test::SharedSequence(o);
}

TEST(SlamSynthetic, StaticSceneSequentialIsAccurate) {
  const fs::path seq = Static();
  const Outcome a = RunOn(seq, /*sequential=*/true);
  EXPECT_EQ(a.tracked, a.frames);
  EXPECT_TRUE(a.map_problems.empty()) << a.map_problems.front();
  const auto ate = eval::ComputeAte(ReadTumTrajectory(seq / "groundtruth.txt"), a.trajectory, FromSeconds(0.02));
  EXPECT_LT(ate.stats.rmse, 0.01);
  EXPECT_EQ(ate.stats.count, a.frames);
  EXPECT_EQ(static_cast<std::size_t>(a.last_map_keyframes), a.keyframes);  // the size frames.csv reports
}

// The names of this process's threads that are sgslam's own ("sg-...").
std::vector<std::string> SgslamThreads() {
  std::vector<std::string> names;
  for (const auto& task : fs::directory_iterator("/proc/self/task")) {
    std::ifstream comm(task.path() / "comm");
    std::string name;
    if (std::getline(comm, name) && name.rfind("sg-", 0) == 0) names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

// Every thread of a parallel run is named, and none outlives the system.
TEST(SlamSynthetic, ThreadsAreNamedAndNoneOutlivesTheSystem) {
  const fs::path seq = Static();
  RunConfig rc = ResolveRunConfig(std::nullopt, seq);
  const TumDataset dataset(seq, rc.config.dataset);
  {
    SlamSystem system(rc.config, /*sequential=*/false);
    FrameStream stream(dataset, rc.config.camera, 2, 10);
    while (auto frame = stream.Next()) system.Process(*frame);
    const auto running = SgslamThreads();
    for (const char* role : {"sg-mapping", "sg-semantic"}) {
      EXPECT_NE(std::find(running.begin(), running.end(), role), running.end()) << role << " not in " << ::testing::PrintToString(running);
    }
    system.Finish();
  }
  EXPECT_EQ(SgslamThreads(), std::vector<std::string>{});
}

TEST(SlamSynthetic, StaticSceneParallelTracksEveryFrame) {
  const fs::path seq = Static();
  const Outcome a = RunOn(seq, /*sequential=*/false);
  EXPECT_GE(a.tracked, a.frames - 1);
  EXPECT_TRUE(a.map_problems.empty()) << a.map_problems.front();
  const auto ate = eval::ComputeAte(ReadTumTrajectory(seq / "groundtruth.txt"), a.trajectory, FromSeconds(0.02));
  EXPECT_LT(ate.stats.rmse, 0.015);
}

// mapping.max_keyframes: the map stops growing at the bound, and the frames after
// are tracked in it (localisation), so the whole run stays tracked and accurate.
TEST(SlamSynthetic, ABoundedMapStopsGrowingAndFramesAreTrackedInIt) {
  const fs::path seq = Static();
  const Outcome free = RunOn(seq, /*sequential=*/true);
  const int bound = static_cast<int>(free.keyframes) / 2;
  ASSERT_GE(bound, 3);
  const Outcome bounded =
      RunOn(seq, /*sequential=*/true, {0, 0}, 0, nullptr, [&](Config& c) { c.mapping.max_keyframes = bound; });
  EXPECT_LE(bounded.keyframes, static_cast<std::size_t>(bound));
  EXPECT_TRUE(bounded.map_problems.empty()) << bounded.map_problems.front();
  EXPECT_EQ(bounded.tracked, bounded.frames);
  const auto ate = eval::ComputeAte(ReadTumTrajectory(seq / "groundtruth.txt"), bounded.trajectory, FromSeconds(0.02));
  EXPECT_LT(ate.stats.rmse, 0.015);
}

// mapping.final_ba_iterations (on by default): one bundle adjustment of the whole
// map when the sequence ends. Every keyframe takes part, the map stays consistent, the
// trajectory (exported relative to the keyframes) follows and is no worse.
TEST(SlamSynthetic, FinalBundleAdjustmentRefinesTheWholeMap) {
  const fs::path seq = Static();
  const auto gt = ReadTumTrajectory(seq / "groundtruth.txt");
  const Outcome plain =
      RunOn(seq, /*sequential=*/true, {0, 0}, 0, nullptr, [](Config& c) { c.mapping.final_ba_iterations = 0; });
  EXPECT_FALSE(plain.final_ba.has_value());
  const auto with_final_ba = [](Config& c) { c.mapping.final_ba_iterations = 10; };
  const Outcome a = RunOn(seq, /*sequential=*/true, {0, 0}, 0, nullptr, with_final_ba);
  ASSERT_TRUE(a.final_ba.has_value());
  EXPECT_TRUE(a.final_ba->ba_done);
  EXPECT_EQ(static_cast<std::size_t>(a.final_ba->local_keyframes), a.keyframes);
  EXPECT_GT(a.final_ba->local_points, 100);
  EXPECT_TRUE(a.map_problems.empty()) << a.map_problems.front();
  const double before = eval::ComputeAte(gt, plain.trajectory, FromSeconds(0.02)).stats.rmse;
  const double after = eval::ComputeAte(gt, a.trajectory, FromSeconds(0.02)).stats.rmse;
  EXPECT_LT(after, 0.01);
  EXPECT_LE(after, before + 1e-4) << "before " << before;
  bool moved = false;
  for (std::size_t i = 0; i < a.trajectory.size() && !moved; ++i) {
    moved = !a.trajectory[i].T_w_c.translation().isApprox(plain.trajectory[i].T_w_c.translation(), 1e-12);
  }
  EXPECT_TRUE(moved) << "the final BA left every pose where it was";
}

// Lost for 15 frames while the camera moves on: the frames after the gap find the
// map again (descriptor matches with recent keyframes, PnP RANSAC) instead of
// staying lost, and the map is not corrupted meanwhile.
TEST(SlamSynthetic, FindsTheMapAgainAfterBlankFrames) {
  const fs::path seq = Static();
  const Outcome a = RunOn(seq, /*sequential=*/true, {50, 100});
  EXPECT_GE(a.tracked, a.frames - 51);
  EXPECT_TRUE(a.map_problems.empty()) << a.map_problems.front();
  const auto ate = eval::ComputeAte(ReadTumTrajectory(seq / "groundtruth.txt"), a.trajectory, FromSeconds(0.02));
  EXPECT_LT(ate.stats.rmse, 0.015);
}

// A first frame that keeps only a corner's keypoints would start a map of a few
// dozen points, which the next frame may never find again: the map waits for a
// frame that keeps half of min_init_points keypoints with depth (at most 5 frames).
TEST(SlamSynthetic, InitialisationWaitsForEnoughKeptKeypoints) {
  const fs::path seq = Static();
  std::vector<TrackState> states;
  const Outcome a = RunOn(seq, /*sequential=*/true, {0, 0}, /*covered=*/2, &states);
  ASSERT_GE(states.size(), 3u);
  EXPECT_EQ(states[0], TrackState::kNotInitialized);
  EXPECT_EQ(states[1], TrackState::kNotInitialized);
  EXPECT_EQ(states[2], TrackState::kOk);
  EXPECT_EQ(a.tracked, a.frames - 2);
  const auto ate = eval::ComputeAte(ReadTumTrajectory(seq / "groundtruth.txt"), a.trajectory, FromSeconds(0.02));
  EXPECT_LT(ate.stats.rmse, 0.01);

  // A scene that stays covered still starts, after the 5 frames of waiting.
  states.clear();
  const Outcome b = RunOn(seq, /*sequential=*/true, {0, 0}, /*covered=*/20, &states);
  ASSERT_GE(states.size(), 6u);
  EXPECT_EQ(states[4], TrackState::kNotInitialized);
  EXPECT_NE(states[5], TrackState::kNotInitialized);
}

// dynamic.refinements.first_frame_rejudge: the first frame has no flow, so sg judges it by its
// boxes alone. A false "person" box over most of frame 0 of a static scene (as
// Yolo-Fastest gives on fr1_rpy) then kept its keypoints out of the first keyframe
// and frame 1 could barely track. Judged again with frame 1 as the other image,
// the static ones join the map before frame 1 is tracked.
TEST(SlamSynthetic, AFalseBoxInTheFirstFrameIsJudgedAgainWithTheNext) {
  const test::TempDir dir;
  const fs::path seq = dir / "static_false_box";
  fs::create_directories(seq);
  fs::copy(Static(), seq, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  std::string first_stamp;
  {
    std::ifstream rgb(seq / "rgb.txt");
    std::string line;
    while (std::getline(rgb, line) && (line.empty() || line[0] == '#')) {
    }
    first_stamp = line.substr(0, line.find(' '));
  }
  {
    std::ofstream det(seq / "detections.txt");
    det << "# detections: timestamp class_id score x0 y0 x1 y1 class_name (box in px)\n"
        << first_stamp << " 0 0.3 300 0 640 480 person\n";  // the right half of the image
  }
  struct Start {
    FrameReport first, second;
    Outcome out;
  };
  const auto run = [&](bool rejudge, bool with_box) {
    RunConfig rc = ResolveRunConfig(std::nullopt, seq);
    rc.config.dynamic.mode = "sg";
    rc.config.dynamic.refinements.first_frame_rejudge = rejudge;
    const TumDataset dataset(seq, rc.config.dataset);
    std::unique_ptr<Detector> detector;
    if (with_box) detector = MakeDetector(rc.config.detector, seq);
    SlamSystem system(rc.config, /*sequential=*/true, std::move(detector));
    FrameStream stream(dataset, rc.config.camera, 2);
    Start s;
    while (auto frame = stream.Next()) {
      if (frame->index >= 40) break;  // the start is what counts
      const FrameReport r = system.Process(*frame);
      if (frame->index == 0) s.first = r;
      if (frame->index == 1) s.second = r;
      ++s.out.frames;
      s.out.tracked += r.state == TrackState::kOk;
    }
    system.Finish();
    s.out.trajectory = system.FrameTrajectory();
    s.out.map_problems = system.CheckMap();
    return s;
  };
  const Start again = run(true, true), boxes_only = run(false, true), clear = run(true, false);
  // The box took most of frame 0's keypoints either way (its labels as reported then).
  EXPECT_LT(again.first.kept, again.first.features / 2);
  EXPECT_EQ(again.first.kept, boxes_only.first.kept);
  std::printf("frame 1 inliers: judged again %d, boxes alone %d, no box %d\n", again.second.inliers,
              boxes_only.second.inliers, clear.second.inliers);
  EXPECT_GT(again.second.inliers, 0.8 * clear.second.inliers);
  EXPECT_LT(boxes_only.second.inliers, 0.6 * clear.second.inliers) << "the false box no longer costs: the test shows nothing";
  EXPECT_EQ(again.out.tracked, again.out.frames);
  EXPECT_TRUE(again.out.map_problems.empty()) << again.out.map_problems.front();
  const auto gt = ReadTumTrajectory(seq / "groundtruth.txt");
  EXPECT_LT(eval::ComputeAte(gt, again.out.trajectory, FromSeconds(0.02)).stats.rmse, 0.01);
}

// A small ORB budget (400 keypoints, fewer than min_init_points' 500 with depth)
// still starts the map on the first frame: the requirement is capped at half the
// budget, as a user lowering orb.features for speed expects.
TEST(SlamSynthetic, StartsWithASmallOrbBudget) {
  const fs::path seq = Static();
  std::vector<TrackState> states;
  const Outcome a = RunOn(seq, /*sequential=*/true, {0, 0}, 0, &states, [](Config& c) { c.orb.features = 400; });
  ASSERT_FALSE(states.empty());
  EXPECT_EQ(states[0], TrackState::kOk);
  EXPECT_GE(a.tracked, a.frames - 1);
  const auto ate = eval::ComputeAte(ReadTumTrajectory(seq / "groundtruth.txt"), a.trajectory, FromSeconds(0.02));
  EXPECT_LT(ate.stats.rmse, 0.02);
}

// Trusted map points (tracking/trusted_pose.h) with no dynamic rejection at all
// (--mode none): people walking through the view put fresh points into the map at
// every keyframe; when those points alone may not set the pose until they have
// stayed put for a while (kTrustDelay), the walkers no longer drag the camera along.
TEST(SlamSynthetic, TrustedMapPointsHoldThePoseAgainstWalkers) {
  const fs::path seq = Walkers();
  const auto gt = ReadTumTrajectory(seq / "groundtruth.txt");
  const auto none = [](Config& c) { c.dynamic.mode = "none"; };
  const Outcome trusted = RunOn(seq, /*sequential=*/true, {0, 0}, 0, nullptr, none);
  const Outcome every = RunOn(seq, /*sequential=*/true, {0, 0}, 0, nullptr, [&](Config& c) {
    none(c);
    c.tracking.refinements.trusted_points = false;  // ORB-SLAM2: every match sets the pose
  });
  EXPECT_EQ(trusted.tracked, trusted.frames);
  EXPECT_TRUE(trusted.map_problems.empty()) << trusted.map_problems.front();
  const double with_trust = eval::ComputeAte(gt, trusted.trajectory, FromSeconds(0.02)).stats.rmse;
  const double without = eval::ComputeAte(gt, every.trajectory, FromSeconds(0.02)).stats.rmse;
  EXPECT_LT(with_trust, 0.02);
  EXPECT_GT(without, 0.1) << "the walkers no longer disturb plain tracking: this test shows nothing";
}

// tracking.refinements.keyframe_velocity_central: with a rolling shutter (camera.readout) a
// keyframe goes to local mapping one frame late, its keypoints corrected with the
// angular velocity of the frames on either side. The synthetic images have a
// global shutter, so a readout only adds error here, whichever velocity corrects
// the keypoints: the point is that the waiting keyframes all reach local mapping
// (a keyframe made at the last frame too, when the run makes one there: nothing
// here forces it), the map stays consistent and accurate, sequentially and in
// parallel, and the correction does act.
TEST(SlamSynthetic, KeyFramesWaitForTheNextFrameWithARollingShutter) {
  const fs::path seq = Static();
  const auto gt = ReadTumTrajectory(seq / "groundtruth.txt");
  const auto shutter = [](bool central) {
    return [central](Config& c) {
      c.camera.readout = 0.03;
      c.tracking.refinements.keyframe_velocity_central = central;
    };
  };
  std::optional<Outcome> central;
  for (const bool sequential : {true, false}) {
    SCOPED_TRACE(sequential ? "sequential" : "parallel");
    const Outcome waits = RunOn(seq, sequential, {0, 0}, 0, nullptr, shutter(true));
    EXPECT_GE(waits.tracked, waits.frames - 1);
    EXPECT_TRUE(waits.map_problems.empty()) << waits.map_problems.front();
    EXPECT_GT(waits.keyframes_made, 3u);
    EXPECT_EQ(waits.keyframes_mapped, waits.keyframes_made);
    EXPECT_LT(eval::ComputeAte(gt, waits.trajectory, FromSeconds(0.02)).stats.rmse, 0.015);
    if (sequential) central = waits;
  }
  const Outcome fitted = RunOn(seq, /*sequential=*/true, {0, 0}, 0, nullptr, shutter(false));
  ASSERT_EQ(fitted.trajectory.size(), central->trajectory.size());
  double moved = 0;
  for (std::size_t i = 0; i < fitted.trajectory.size(); ++i) {
    moved = std::max(moved, (fitted.trajectory[i].T_w_c.translation() - central->trajectory[i].T_w_c.translation()).norm());
  }
  EXPECT_GT(moved, 1e-6) << "the keyframes' correction changed nothing";
}

// A sequence rendered with a rolling shutter (synth --preset rpy --readout 0.03;
// its sgslam.yaml gives the readout): taken for a global shutter the trajectory is
// 8x worse; the keypoints corrected with the fitted angular velocity fix most of
// it; the keyframes corrected again with the central difference of the poses on
// either side (tracking.refinements.keyframe_velocity_central; the first keyframe with the
// step to the next frame) halve what is left. The exported frames' refit
// (frame_velocity_central) leaves tracking as it was; here it does not gain
// (0.0073 m against 0.0063), on TUM's fr1_rpy it does (README "Rolling shutter").
TEST(SlamSynthetic, RollingShutterCorrectionFollowsARenderedRollingShutter) {
  const fs::path seq = Rolling();
  const auto gt = ReadTumTrajectory(seq / "groundtruth.txt");
  const auto ate = [&](const Trajectory& t) { return eval::ComputeAte(gt, t, FromSeconds(0.02)).stats.rmse; };
  const Outcome global = RunOn(seq, true, {0, 0}, 0, nullptr, [](Config& c) { c.camera.readout = 0; });
  const Outcome fitted = RunOn(seq, true, {0, 0}, 0, nullptr, [](Config& c) {
    EXPECT_DOUBLE_EQ(c.camera.readout, 0.03) << "the readout comes from the sequence's sgslam.yaml";
    c.tracking.refinements.keyframe_velocity_central = false;
    c.tracking.refinements.frame_velocity_central = false;
  });
  const Outcome keyframes = RunOn(seq, true, {0, 0}, 0, nullptr, [](Config& c) { c.tracking.refinements.frame_velocity_central = false; });
  const Outcome central = RunOn(seq, true);
  for (const Outcome* o : {&global, &fitted, &keyframes, &central}) {
    EXPECT_EQ(o->tracked, o->frames);
    EXPECT_TRUE(o->map_problems.empty()) << o->map_problems.front();
  }
  std::printf("rolling shutter ATE: as global %.4f m, fitted w %.4f m, keyframes central %.4f m, frames too %.4f m "
              "(online %.4f m)\n", ate(global.trajectory), ate(fitted.trajectory), ate(keyframes.trajectory),
              ate(central.trajectory), ate(central.online));
  EXPECT_LT(ate(fitted.trajectory), ate(global.trajectory) / 4) << "the rows' shear is not corrected";
  EXPECT_LT(ate(keyframes.trajectory), 0.75 * ate(fitted.trajectory));  // 0.0063 against 0.0136 m
  EXPECT_LT(ate(central.trajectory), 0.012);
  // The frames' refit changes only what is exported: tracking, the map and the
  // live poses are those of the run without it, bit for bit.
  ASSERT_EQ(central.online.size(), keyframes.online.size());
  for (std::size_t i = 0; i < central.online.size(); ++i) {
    ASSERT_EQ(central.online[i].T_w_c.translation(), keyframes.online[i].T_w_c.translation()) << i;
  }
  ASSERT_EQ(central.trajectory.size(), keyframes.trajectory.size());
  std::size_t refitted = 0;
  for (std::size_t i = 0; i < central.trajectory.size(); ++i) {
    refitted += central.trajectory[i].T_w_c.translation() != keyframes.trajectory[i].T_w_c.translation();
  }
  EXPECT_GT(refitted, central.trajectory.size() / 2) << "most frames are fitted again";
}

}  // namespace
}  // namespace sgslam
