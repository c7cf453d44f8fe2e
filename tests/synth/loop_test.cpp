// The loop preset: a closed path of 20 m or more walked twice at walking pace,
// views that stay textured and within the depth sensor's range, and a second
// lap that sees what the first saw.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "sgslam/features/orb_extractor.h"
#include "sgslam/synth/loop_scenes.h"
#include "sgslam/synth/presets.h"
#include "sgslam/synth/sequence.h"

namespace sgslam::synth {
namespace {

const int kLapFrames = static_cast<int>(kLoopLapSeconds * kFps);

SynthSequence LoopSequence(std::uint32_t seed) {
  const PresetDefaults d = DefaultsOf("loop");
  return SynthSequence("loop", seed, d.frames, d.readout, d.depth_noise);
}

TEST(SynthLoop, DefaultsCoverTwoLapsWithAKinectLikeSensor) {
  const PresetDefaults d = DefaultsOf("loop");
  EXPECT_EQ(d.frames, 2 * kLapFrames + 1);
  EXPECT_GT(d.readout, 0);
  EXPECT_EQ(d.depth_noise, DepthNoise::kKinect);
  EXPECT_NE(std::find(PresetNames().begin(), PresetNames().end(), "loop"), PresetNames().end());
}

TEST(SynthLoop, TwoClosedLapsOfTwentyMetresAtWalkingPace) {
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    const SynthSequence seq = LoopSequence(seed);
    EXPECT_GE(seq.scene().camera.loop.Length(), 20.0) << "seed " << seed;
    for (int lap = 0; lap < kLoopLaps; ++lap) {
      const int first = lap * kLapFrames, last = first + kLapFrames;
      double length = 0, max_speed = 0, max_turn = 0;
      for (int i = first; i < last; ++i) {
        const SE3 a = seq.CameraPose(i), b = seq.CameraPose(i + 1);
        const double dt = seq.Seconds(i + 1) - seq.Seconds(i);
        length += (b.translation() - a.translation()).norm();
        max_speed = std::max(max_speed, (b.translation() - a.translation()).norm() / dt);
        max_turn = std::max(max_turn, a.quaternion().angularDistance(b.quaternion()) / dt);
      }
      const SE3 start = seq.CameraPose(first), end = seq.CameraPose(last);
      std::printf("seed %u lap %d: %.2f m, max %.2f m/s, %.2f rad/s; closes within %.3f m, %.3f rad\n", seed, lap,
                  length, max_speed, max_turn, (end.translation() - start.translation()).norm(),
                  start.quaternion().angularDistance(end.quaternion()));
      EXPECT_GE(length, 20.0);
      EXPECT_LT(max_speed, 0.9);
      EXPECT_LT(max_turn, 0.8);
      EXPECT_LT((end.translation() - start.translation()).norm(), 0.03);  // the same place, a lap later
      EXPECT_LT(start.quaternion().angularDistance(end.quaternion()), 0.2);
    }
  }
}

bool SameBytes(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::countNonZero(a.reshape(1) != b.reshape(1)) == 0;
}

TEST(SynthLoop, LoopAndRepeatAreDeterministicPerSeed) {
  for (const char* preset : {"loop", "repeat"}) {
    const PresetDefaults d = DefaultsOf(preset);
    const SynthSequence a(preset, 1, 40, d.readout, d.depth_noise), b(preset, 1, 40, d.readout, d.depth_noise);
    const SynthSequence c(preset, 2, 40, d.readout, d.depth_noise);
    const RenderedFrame fa = a.Render(33), fb = b.Render(33), fc = c.Render(33);
    EXPECT_TRUE(SameBytes(fa.bgr, fb.bgr)) << preset;
    EXPECT_TRUE(SameBytes(fa.depth_raw, fb.depth_raw)) << preset;
    EXPECT_FALSE(SameBytes(fa.bgr, fc.bgr)) << preset;
    EXPECT_GT((a.CameraPose(0).translation() - c.CameraPose(0).translation()).norm(), 1e-3) << preset;
  }
}

// Unit speed along the path, a tangent that matches Heading, and a gaze heading
// that turns smoothly, a full turn a lap, never far from the tangent.
TEST(SynthLoop, LoopPathIsContinuousAndTheGazeTurnsSmoothly) {
  LoopPath loop;
  loop.centre = {5, 3};
  loop.half_size = {4, 2};
  loop.corner = 1.2;
  const double ds = 1e-3, length = loop.Length();
  EXPECT_NEAR(length, 2 * (5.6 + 1.6) + 2 * std::numbers::pi * 1.2, 1e-12);
  const double width = 0.5 * std::numbers::pi * loop.corner + 2 * loop.turn_margin;
  const double max_rate = 0.25 * std::numbers::pi * std::numbers::pi / width;  // rad/m, mid-ramp
  for (double s = -length; s < 2 * length; s += 0.01) {
    const Eigen::Vector2d step = loop.Point(s + ds) - loop.Point(s);
    ASSERT_NEAR(step.norm(), ds, 1e-6) << s;
    const double tangent = std::atan2(step.y(), step.x());
    ASSERT_LT(std::abs(std::remainder(tangent - loop.Heading(s), 2 * std::numbers::pi)), 2e-3) << s;
    const double turn = loop.GazeHeading(s + ds) - loop.GazeHeading(s);
    ASSERT_GE(turn, 0) << s;
    ASSERT_LE(turn, max_rate * ds * 1.001) << s;
    ASSERT_LT(std::abs(std::remainder(loop.GazeHeading(s) - loop.Heading(s), 2 * std::numbers::pi)), 0.5) << s;
    ASSERT_NEAR(loop.GazeHeading(s + length), loop.GazeHeading(s) + 2 * std::numbers::pi, 1e-9) << s;
  }
  EXPECT_NEAR(loop.Point(0).x(), 5, 1e-12);  // arc length 0: the middle of the -y side
  EXPECT_NEAR(loop.Point(0).y(), 1, 1e-12);
}

TEST(SynthLoop, TheCameraWalksInsideTheHallAtHandHeight) {
  const SynthSequence seq = LoopSequence(1);
  const Eigen::Vector3d size = seq.scene().room_size;
  for (int i = 0; i < seq.size(); i += 10) {
    const Eigen::Vector3d p = seq.CameraPose(i).translation();
    EXPECT_TRUE((p.array() > 1.4).all() && (p.head<2>().array() < size.head<2>().array() - 1.4).all()) << i;
    EXPECT_NEAR(p.z(), 1.52, 0.1);
  }
}

// Depth within the sensor's range nearly everywhere, and rich texture: ORB finds
// its whole budget, FAST-20 more corners than in most fr1_rpy frames (200-1000).
TEST(SynthLoop, FramesHaveValidDepthAndManyCorners) {
  const SynthSequence seq = LoopSequence(1);
  features::OrbExtractor orb(OrbConfig{});
  for (int i = 0; i < seq.size(); i += 150) {
    const RenderedFrame f = seq.Render(i);
    std::vector<float> z;
    for (int y = 0; y < f.depth.rows; ++y) {
      for (int x = 0; x < f.depth.cols; ++x) z.push_back(f.depth.at<float>(y, x));
    }
    std::sort(z.begin(), z.end());
    const double valid = cv::countNonZero(f.depth_raw) / static_cast<double>(f.depth_raw.total());
    cv::Mat gray;
    cv::cvtColor(f.bgr, gray, cv::COLOR_BGR2GRAY);
    std::vector<cv::KeyPoint> keypoints, fast;
    cv::Mat descriptors;
    orb.Extract(gray, keypoints, descriptors);
    cv::FAST(gray, fast, 20);
    std::printf("frame %4d: depth %.2f / %.2f / %.2f m (min / median / 98 %%), %.1f %% valid, %zu ORB, %zu FAST\n", i,
                z.front(), z[z.size() / 2], z[z.size() * 98 / 100], 100 * valid, keypoints.size(), fast.size());
    EXPECT_GT(z.front(), 0.5) << i;
    EXPECT_GT(z[z.size() / 2], 1.2) << i;
    EXPECT_LT(z[z.size() * 98 / 100], 5.0) << i;
    EXPECT_GT(valid, 0.85) << i;
    EXPECT_GE(keypoints.size(), 950u) << i;
    EXPECT_GE(fast.size(), 1200u) << i;
  }
}

// Share of the points frame b sees (a grid of its pixels) that frame a sees too:
// in a's image, at a's depth there. Global-shutter frames: one pose per frame.
double CoVisible(const RenderedFrame& a, const RenderedFrame& b, const Intrinsics& K) {
  const SE3 T_ca_cb = a.T_w_c.Inverse() * b.T_w_c;
  int seen = 0, total = 0;
  for (int v = 4; v < K.height; v += 8) {
    for (int u = 4; u < K.width; u += 8) {
      const float z = b.depth.at<float>(v, u);
      if (z <= 0) continue;
      ++total;
      const Eigen::Vector3d p = T_ca_cb * (z * K.Ray(u, v));
      const long pu = std::lround(K.fx * p.x() / p.z() + K.cx), pv = std::lround(K.fy * p.y() / p.z() + K.cy);
      if (p.z() <= 0 || pu < 0 || pv < 0 || pu >= K.width || pv >= K.height) continue;
      seen += std::abs(a.depth.at<float>(static_cast<int>(pv), static_cast<int>(pu)) - p.z()) < 0.05 * p.z();
    }
  }
  return total > 0 ? static_cast<double>(seen) / total : 0;
}

// A frame of the second lap and the first lap's frame at the same place see
// mostly the same points.
TEST(SynthLoop, TheSecondLapSeesWhatTheFirstSaw) {
  const SynthSequence seq("loop", 2, DefaultsOf("loop").frames);
  for (int i = 0; i < kLapFrames; i += 150) {
    const RenderedFrame a = seq.Render(i), b = seq.Render(i + kLapFrames);
    const double shared = CoVisible(a, b, seq.intrinsics());
    std::printf("frames %d and %d: %.1f %% of the points seen by both, %.3f m apart\n", i, i + kLapFrames, 100 * shared,
                (a.T_w_c.translation() - b.T_w_c.translation()).norm());
    EXPECT_GT(shared, 0.8) << i;
  }
}

}  // namespace
}  // namespace sgslam::synth
