// End to end on synthetic sequences with exact ground truth: the whole system in
// sequential mode must track a static scene to within a centimetre and give the
// same trajectory bit for bit on every run.
#include <gtest/gtest.h>

#include <shared_mutex>

#include "sgslam/eval/ate.h"
#include "sgslam/io/frame_stream.h"
#include "sgslam/map/map_check.h"
#include "sgslam/synth/writer.h"
#include "sgslam/system/run_config.h"
#include "sgslam/system/slam_system.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  Trajectory trajectory;
  std::size_t frames = 0, tracked = 0;
  std::vector<std::string> map_problems;
};

// blank: frames [first, last) arrive black and without depth (a covered lens).
// covered: the first `covered` frames have all but their top-left 120x90 px
// marked moving (dynamic.truth_masks' path), as a frame whose false-positive
// boxes cover nearly everything would be.
Outcome RunOn(const fs::path& dir, bool sequential, std::pair<std::size_t, std::size_t> blank = {0, 0},
              std::size_t covered = 0, std::vector<TrackState>* states = nullptr) {
  const RunConfig rc = ResolveRunConfig(std::nullopt, dir);
  const TumDataset dataset(dir, rc.config.dataset);
  SlamSystem system(rc.config, sequential);
  FrameStream stream(dataset, rc.config.camera, 2);
  Outcome out;
  while (auto frame = stream.Next()) {
    if (frame->index >= blank.first && frame->index < blank.second) {
      frame->bgr = cv::Mat::zeros(frame->bgr.size(), frame->bgr.type());
      frame->depth = cv::Mat::zeros(frame->depth.size(), frame->depth.type());
    }
    if (frame->index < covered) {
      frame->truth_mask = cv::Mat(frame->bgr.size(), CV_8UC1, cv::Scalar(255));
      frame->truth_mask(cv::Rect(0, 0, 120, 90)).setTo(0);
    }
    const FrameReport r = system.Process(*frame);
    if (states) states->push_back(r.state);
    ++out.frames;
    out.tracked += r.state == TrackState::kOk;
  }
  system.Finish();
  out.trajectory = system.FrameTrajectory();
  out.map_problems = system.CheckMap();
  return out;
}

class SlamSynthetic : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    synth::SynthOptions o;
    o.preset = "static";
    o.frames = 150;
    o.seed = 3;
    synth::GenerateSequence(o, dir_->path() / "static");
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static test::TempDir* dir_;
};
test::TempDir* SlamSynthetic::dir_ = nullptr;

TEST_F(SlamSynthetic, StaticSceneSequentialIsAccurateAndDeterministic) {
  const fs::path seq = dir_->path() / "static";
  const Outcome a = RunOn(seq, /*sequential=*/true);
  EXPECT_EQ(a.tracked, a.frames);
  EXPECT_TRUE(a.map_problems.empty()) << a.map_problems.front();
  const auto ate = eval::ComputeAte(ReadTumTrajectory(seq / "groundtruth.txt"), a.trajectory, FromSeconds(0.02));
  EXPECT_LT(ate.stats.rmse, 0.01);
  EXPECT_EQ(ate.stats.count, a.frames);

  const Outcome b = RunOn(seq, /*sequential=*/true);
  ASSERT_EQ(a.trajectory.size(), b.trajectory.size());
  for (std::size_t i = 0; i < a.trajectory.size(); ++i) {
    EXPECT_EQ(a.trajectory[i].T_w_c.translation(), b.trajectory[i].T_w_c.translation()) << i;
    EXPECT_EQ(a.trajectory[i].T_w_c.quaternion().coeffs(), b.trajectory[i].T_w_c.quaternion().coeffs()) << i;
  }
}

TEST_F(SlamSynthetic, StaticSceneParallelTracksEveryFrame) {
  const fs::path seq = dir_->path() / "static";
  const Outcome a = RunOn(seq, /*sequential=*/false);
  EXPECT_GE(a.tracked, a.frames - 1);
  EXPECT_TRUE(a.map_problems.empty()) << a.map_problems.front();
  const auto ate = eval::ComputeAte(ReadTumTrajectory(seq / "groundtruth.txt"), a.trajectory, FromSeconds(0.02));
  EXPECT_LT(ate.stats.rmse, 0.015);
}

// Lost for 15 frames while the camera moves on: the frames after the gap find the
// map again (descriptor matches with recent keyframes, PnP RANSAC) instead of
// staying lost, and the map is not corrupted meanwhile.
TEST_F(SlamSynthetic, FindsTheMapAgainAfterBlankFrames) {
  const fs::path seq = dir_->path() / "static";
  const Outcome a = RunOn(seq, /*sequential=*/true, {50, 100});
  EXPECT_GE(a.tracked, a.frames - 51);
  EXPECT_TRUE(a.map_problems.empty()) << a.map_problems.front();
  const auto ate = eval::ComputeAte(ReadTumTrajectory(seq / "groundtruth.txt"), a.trajectory, FromSeconds(0.02));
  EXPECT_LT(ate.stats.rmse, 0.015);
}

// A first frame that keeps only a corner's keypoints would start a map of a few
// dozen points, which the next frame may never find again: the map waits for a
// frame that keeps half of min_init_points keypoints with depth (at most 5 frames).
TEST_F(SlamSynthetic, InitialisationWaitsForEnoughKeptKeypoints) {
  const fs::path seq = dir_->path() / "static";
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

}  // namespace
}  // namespace sgslam
