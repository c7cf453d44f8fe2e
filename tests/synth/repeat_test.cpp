// The repeat preset: a corridor of identical modules walked once along, so that
// places one module apart look alike while no place is visited twice.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "sgslam/features/orb_extractor.h"
#include "sgslam/synth/loop_scenes.h"
#include "sgslam/synth/presets.h"
#include "sgslam/synth/sequence.h"

namespace sgslam::synth {
namespace {

double Period(const SynthSequence& seq) { return seq.scene().room_size.x() / kRepeatModules; }

TEST(SynthRepeat, OneWayAlongFourModulesAtWalkingPace) {
  const PresetDefaults d = DefaultsOf("repeat");
  EXPECT_EQ(d.depth_noise, DepthNoise::kKinect);
  for (std::uint32_t seed : {1u, 2u}) {
    const SynthSequence seq("repeat", seed, d.frames);
    double max_speed = 0;
    for (int i = 0; i + 1 < seq.size(); ++i) {
      const Eigen::Vector3d a = seq.CameraPose(i).translation(), b = seq.CameraPose(i + 1).translation();
      EXPECT_GE(b.x(), a.x()) << "frame " << i;  // never back: no place seen twice from the same spot
      max_speed = std::max(max_speed, (b - a).norm() / (seq.Seconds(i + 1) - seq.Seconds(i)));
    }
    const double travel = seq.CameraPose(seq.size() - 1).translation().x() - seq.CameraPose(0).translation().x();
    std::printf("seed %u: %.2f m along, %.2f m modules, max %.2f m/s\n", seed, travel, Period(seq), max_speed);
    EXPECT_NEAR(travel, (kRepeatModules - 1) * Period(seq), 0.1);
    EXPECT_LT(max_speed, 0.9);
  }
}

// The view from a pose and from that pose moved by one or two modules is the same
// image (same time, same noise), 3.3 m or more apart.
TEST(SynthRepeat, PlacesOneModuleApartLookTheSame) {
  const SynthSequence seq("repeat", 1, DefaultsOf("repeat").frames);
  const int i = seq.size() / 4;  // in the second module
  const RenderedFrame f = seq.Render(i);
  for (int k = 1; k <= 2; ++k) {
    const SE3 moved(f.T_w_c.quaternion(), f.T_w_c.translation() + k * Period(seq) * Eigen::Vector3d::UnitX());
    const RenderedFrame g = RenderFrame(seq.scene(), seq.intrinsics(), moved, seq.Seconds(i), i, 0);
    const RenderedFrame h = RenderFrame(seq.scene(), seq.intrinsics(), f.T_w_c, seq.Seconds(i), i, 0);
    cv::Mat diff;
    cv::absdiff(g.bgr, h.bgr, diff);
    const double same = cv::countNonZero(diff.reshape(1) <= 2) / static_cast<double>(diff.total() * 3);
    std::printf("moved by %d modules (%.2f m): %.2f %% of the pixel values within 2\n", k, k * Period(seq), 100 * same);
    EXPECT_GT(same, 0.99);
  }
}

// Appearance alone would close a false loop: ORB features of a frame and of the
// frame one module further match like those of one place, but their points lie a
// module apart.
TEST(SynthRepeat, FeaturesMatchAcrossModulesAtPointsAModuleApart) {
  const SynthSequence seq("repeat", 1, DefaultsOf("repeat").frames);
  const int i = seq.size() / 4;
  int j = i;
  const double target = seq.CameraPose(i).translation().x() + Period(seq);
  while (j + 1 < seq.size() && seq.CameraPose(j).translation().x() < target) ++j;
  features::OrbExtractor orb(OrbConfig{});
  const auto describe = [&](const RenderedFrame& f, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) {
    cv::Mat gray;
    cv::cvtColor(f.bgr, gray, cv::COLOR_BGR2GRAY);
    orb.Extract(gray, keypoints, descriptors);
  };
  const RenderedFrame a = seq.Render(i), b = seq.Render(j);
  std::vector<cv::KeyPoint> ka, kb;
  cv::Mat da, db;
  describe(a, ka, da);
  describe(b, kb, db);
  std::vector<cv::DMatch> matches;
  cv::BFMatcher(cv::NORM_HAMMING, /*crossCheck=*/true).match(da, db, matches);
  std::vector<double> apart;  // world distance of the matched points
  for (const cv::DMatch& m : matches) {
    const cv::Point2f pa = ka[m.queryIdx].pt, pb = kb[m.trainIdx].pt;
    const float za = a.depth.at<float>(cvRound(pa.y), cvRound(pa.x)),
                zb = b.depth.at<float>(cvRound(pb.y), cvRound(pb.x));
    if (m.distance > 40 || za <= 0 || zb <= 0) continue;
    const Eigen::Vector3d wa = a.T_w_c * (za * seq.intrinsics().Ray(pa.x, pa.y));
    const Eigen::Vector3d wb = b.T_w_c * (zb * seq.intrinsics().Ray(pb.x, pb.y));
    apart.push_back((wb - wa).norm());
  }
  std::sort(apart.begin(), apart.end());
  ASSERT_FALSE(apart.empty());
  const double median = apart[apart.size() / 2];
  std::printf("frames %d and %d: %zu good matches of %zu keypoints, median %.2f m apart (module %.2f m)\n", i, j,
              apart.size(), ka.size(), median, Period(seq));
  EXPECT_GE(apart.size(), 200u);
  EXPECT_NEAR(median, Period(seq), 0.15);
}

}  // namespace
}  // namespace sgslam::synth
