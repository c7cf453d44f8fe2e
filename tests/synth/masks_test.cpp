#include <gtest/gtest.h>

#include "sgslam/synth/sequence.h"

namespace sgslam::synth {
namespace {

// The mask must be exactly the pixels whose visible surface belongs to a moving object.
void ExpectMaskMatchesIds(const SynthSequence& seq, const RenderedFrame& f) {
  int mask_pixels = 0, mismatches = 0;
  for (int v = 0; v < f.object_id.rows; ++v) {
    for (int u = 0; u < f.object_id.cols; ++u) {
      const int id = f.object_id.at<int>(v, u);
      const bool moving = id > 0 && seq.objects().at(id - 1).info.dynamic;
      const bool masked = f.dynamic_mask.at<std::uint8_t>(v, u) == 255;
      mismatches += moving != masked;
      mask_pixels += masked;
      EXPECT_TRUE(f.dynamic_mask.at<std::uint8_t>(v, u) == 0 || masked);
    }
  }
  EXPECT_EQ(mismatches, 0) << "frame " << f.index;
  EXPECT_DOUBLE_EQ(f.dynamic_fraction, mask_pixels / double(f.object_id.total()));
}

TEST(SynthMasks, MaskIsExactlyTheMovingObjectsPixels) {
  const SynthSequence seq("walkers", 1, 90);
  int frames_with_mask = 0;
  for (int i = 0; i < seq.size(); i += 15) {
    const RenderedFrame f = seq.Render(i);
    ExpectMaskMatchesIds(seq, f);
    frames_with_mask += f.dynamic_fraction > 0;
  }
  EXPECT_GE(frames_with_mask, 3);
}

TEST(SynthMasks, DegenerateMaskFollowsItsWalker) {
  const SynthSequence seq("degenerate", 1, 60);
  for (int i = 0; i < seq.size(); i += 20) ExpectMaskMatchesIds(seq, seq.Render(i));
}

TEST(SynthMasks, NothingMovesInStaticAndObjects) {
  for (const char* preset : {"static", "objects"}) {
    const SynthSequence seq(preset, 5, 60);
    for (const SceneObject& o : seq.objects()) EXPECT_FALSE(o.info.dynamic) << preset;
    for (int i = 0; i < seq.size(); i += 20) {
      const RenderedFrame f = seq.Render(i);
      EXPECT_EQ(cv::countNonZero(f.dynamic_mask), 0) << preset << " frame " << i;
      EXPECT_EQ(f.dynamic_fraction, 0.0);
    }
  }
}

}  // namespace
}  // namespace sgslam::synth
