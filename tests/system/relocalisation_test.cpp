// Global relocalisation on the real TUM fr1_rpy sequence (skipped without
// ../shared): the camera "kidnapped" by a stretch of frames that never arrive, or
// that arrive black and without depth, is found again by place recognition within
// five frames of the first frame after the gap.
#include <gtest/gtest.h>

#include <filesystem>
#include <optional>

#include "sgslam/io/frame_stream.h"
#include "sgslam/system/run_config.h"
#include "sgslam/system/slam_system.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kGapFirst = 300, kGapEnd = 360;  // frames 300..359
constexpr std::size_t kMaxFramesToRelocalise = 5;

// States by frame index; frames in the gap are dropped, or blanked when `blank`.
std::vector<std::optional<TrackState>> RunKidnapped(const fs::path& dir, bool blank, bool place_recognition) {
  RunConfig rc = ResolveRunConfig(std::nullopt, dir);
  rc.config.dynamic.mode = "none";
  rc.config.semantic.enabled = false;
  rc.config.loop.enabled = place_recognition;
  const TumDataset dataset(dir, rc.config.dataset);
  SlamSystem system(rc.config, /*sequential=*/true);
  FrameStream stream(dataset, rc.config.camera, 2);
  std::vector<std::optional<TrackState>> states(dataset.size());
  while (auto frame = stream.Next()) {
    const bool in_gap = frame->index >= kGapFirst && frame->index < kGapEnd;
    if (in_gap && !blank) continue;
    if (in_gap) {
      frame->bgr = cv::Mat::zeros(frame->bgr.size(), frame->bgr.type());
      frame->depth = cv::Mat::zeros(frame->depth.size(), frame->depth.type());
    }
    states[frame->index] = system.Process(*frame).state;
  }
  system.Finish();
  return states;
}

// Frames after the gap until the first tracked one.
std::size_t FramesToRelocalise(const std::vector<std::optional<TrackState>>& states) {
  for (std::size_t i = kGapEnd; i < states.size(); ++i) {
    if (states[i] == TrackState::kOk) return i - kGapEnd;
  }
  return states.size();
}

TEST(Relocalisation, AfterFramesThatNeverCame) {
  SGSLAM_REQUIRE_SHARED(dir, "data/tum_fr1_rpy");
  const auto states = RunKidnapped(dir, /*blank=*/false, /*place_recognition=*/true);
  EXPECT_LE(FramesToRelocalise(states), kMaxFramesToRelocalise);
  std::size_t lost_after = 0;
  for (std::size_t i = kGapEnd; i < states.size(); ++i) lost_after += states[i] == TrackState::kLost;
  EXPECT_LE(lost_after, kMaxFramesToRelocalise);
}

TEST(Relocalisation, AfterBlackFramesWithoutDepth) {
  SGSLAM_REQUIRE_SHARED(dir, "data/tum_fr1_rpy");
  const auto states = RunKidnapped(dir, /*blank=*/true, /*place_recognition=*/true);
  for (std::size_t i = kGapFirst; i < kGapEnd; ++i) EXPECT_EQ(states[i], TrackState::kLost) << "frame " << i;
  EXPECT_LE(FramesToRelocalise(states), kMaxFramesToRelocalise);
}

}  // namespace
}  // namespace sgslam
