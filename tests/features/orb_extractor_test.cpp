#include "sgslam/features/orb_extractor.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>

#include "feature_test_images.h"
#include "sgslam/common/error.h"
#include "support/test_support.h"

namespace sgslam::features {
namespace {

using test::CornerTexture;
using test::UniformTexture;

struct Extraction {
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
};

Extraction ExtractAll(OrbExtractor& orb, const cv::Mat& image) {
  Extraction e;
  orb.Extract(image, e.kps, e.desc);
  return e;
}

// Largest number of points in any w x w window (windows anchored at point
// coordinates are enough to find the maximum).
int MaxInWindow(const std::vector<cv::Point2f>& pts, float w) {
  int best = 0;
  for (const auto& a : pts) {
    for (const auto& b : pts) {
      int n = 0;
      for (const auto& p : pts) n += (p.x >= a.x && p.x < a.x + w && p.y >= b.y && p.y < b.y + w) ? 1 : 0;
      best = std::max(best, n);
    }
  }
  return best;
}

std::vector<cv::Point2f> LevelZeroPoints(const std::vector<cv::KeyPoint>& kps) {
  std::vector<cv::Point2f> pts;
  for (const auto& kp : kps) {
    if (kp.octave == 0) pts.push_back(kp.pt);
  }
  return pts;
}

TEST(OrbExtractor, ScaleAccessorsFollowTheConfig) {
  OrbExtractor orb(OrbConfig{});
  ASSERT_EQ(orb.levels(), 8);
  for (int l = 0; l < 8; ++l) {
    const double s = std::pow(1.2, l);
    EXPECT_NEAR(orb.scale_factors()[l], s, 1e-9);
    EXPECT_NEAR(orb.inv_scale_factors()[l], 1.0 / s, 1e-9);
    EXPECT_NEAR(orb.level_sigma2()[l], s * s, 1e-9);
    EXPECT_NEAR(orb.inv_level_sigma2()[l], 1.0 / (s * s), 1e-9);
  }
  const auto& n = orb.features_per_level();
  int sum = 0;
  for (size_t l = 0; l < n.size(); ++l) {
    sum += n[l];
    if (l > 0 && l + 1 < n.size()) {
      EXPECT_LT(n[l], n[l - 1]);
    }
  }
  EXPECT_EQ(sum, 1000);
  EXPECT_NEAR(n[0], 1000 * (1 - 1 / 1.2) / (1 - std::pow(1 / 1.2, 8)), 1.0);  // 217
}

TEST(OrbExtractor, RejectsBadConfigAndInput) {
  OrbConfig bad;
  bad.levels = 0;
  EXPECT_THROW(OrbExtractor{bad}, ConfigError);
  OrbExtractor orb(OrbConfig{});
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  EXPECT_THROW(orb.Extract(cv::Mat(480, 640, CV_8UC3), kps, desc), InputError);
  EXPECT_THROW(orb.Extract(cv::Mat(), kps, desc), InputError);
}

TEST(OrbExtractor, UniformTextureSpreadsOverQuadrantsAndLevels) {
  OrbExtractor orb(OrbConfig{});
  const Extraction e = ExtractAll(orb, UniformTexture(1));
  const int n = static_cast<int>(e.kps.size());
  EXPECT_GE(n, 900);
  EXPECT_LE(n, 1000);
  ASSERT_EQ(e.desc.rows, n);
  EXPECT_EQ(e.desc.cols, 32);
  EXPECT_EQ(e.desc.type(), CV_8U);

  int quadrant[4] = {0, 0, 0, 0};
  std::vector<int> per_level(8, 0);
  for (const auto& kp : e.kps) {
    ++quadrant[(kp.pt.x >= 320 ? 1 : 0) + (kp.pt.y >= 240 ? 2 : 0)];
    ++per_level[static_cast<size_t>(kp.octave)];
  }
  for (int q : quadrant)
    EXPECT_GE(q, 0.15 * n) << "quadrant counts " << quadrant[0] << " " << quadrant[1] << " " << quadrant[2] << " "
                           << quadrant[3];
  for (int l = 0; l < 8; ++l) {
    EXPECT_GT(per_level[l], 0.5 * orb.features_per_level()[l]) << "level " << l;
    EXPECT_LE(per_level[l], orb.features_per_level()[l]) << "level " << l;
  }
  const int max_in_window = MaxInWindow(LevelZeroPoints(e.kps), 40.0f);
  RecordProperty("keypoints", n);
  RecordProperty("max_in_40px_window", max_in_window);
  EXPECT_LE(max_in_window, 8);
}

// One corner far more textured than the rest: the quadtree still spreads
// level-0 keypoints over the whole image, where FAST's top-N all pile up there.
TEST(OrbExtractor, NoClumpsOnATexturedCorner) {
  const cv::Mat image = CornerTexture(7);
  OrbExtractor orb(OrbConfig{});
  const Extraction e = ExtractAll(orb, image);
  const std::vector<cv::Point2f> ours = LevelZeroPoints(e.kps);
  ASSERT_GE(ours.size(), 150u);

  std::vector<cv::KeyPoint> fast;
  cv::FAST(image, fast, 7, true);
  cv::KeyPointsFilter::retainBest(fast, static_cast<int>(ours.size()));
  std::vector<cv::Point2f> plain;
  for (const auto& kp : fast) plain.push_back(kp.pt);

  const auto outside_corner_count = [](const std::vector<cv::Point2f>& pts) {
    return static_cast<int>(
        std::count_if(pts.begin(), pts.end(), [](const cv::Point2f& p) { return p.x >= 200 || p.y >= 150; }));
  };
  const int cap = 8;
  const int ours_max = MaxInWindow(ours, 40.0f);
  const int plain_max = MaxInWindow(plain, 40.0f);
  RecordProperty("max_in_40px_window", ours_max);
  RecordProperty("max_in_40px_window_plain_fast", plain_max);
  RecordProperty("level0_outside_corner", outside_corner_count(ours));
  EXPECT_LE(ours_max, cap);
  EXPECT_GT(plain_max, 2 * cap) << "the test image should make plain FAST clump";

  const int outside_corner = outside_corner_count(ours);
  EXPECT_GT(outside_corner, 0.7 * static_cast<double>(ours.size()));  // the corner is 10 % of the image
}

TEST(OrbExtractor, KeypointsAreConsistentWithTheirLevel) {
  OrbExtractor orb(OrbConfig{});
  const cv::Mat image = UniformTexture(2);
  const Extraction e = ExtractAll(orb, image);
  ASSERT_FALSE(e.kps.empty());
  ASSERT_EQ(orb.pyramid().size(), 8u);
  EXPECT_EQ(cv::norm(orb.pyramid()[0], image, cv::NORM_INF), 0.0);
  for (int l = 1; l < 8; ++l) {
    EXPECT_EQ(orb.pyramid()[l].cols, cvRound(640 / orb.scale_factors()[l]));
    EXPECT_EQ(orb.pyramid()[l].rows, cvRound(480 / orb.scale_factors()[l]));
  }
  int prev_octave = 0;
  for (const auto& kp : e.kps) {
    ASSERT_GE(kp.octave, 0);
    ASSERT_LT(kp.octave, 8);
    EXPECT_GE(kp.octave, prev_octave) << "keypoints are grouped by level";
    prev_octave = kp.octave;
    const double s = orb.scale_factors()[kp.octave];
    EXPECT_NEAR(kp.size, 31.0 * s, 1e-3);
    // Level coordinates are integers at least 19 px from the level's border.
    const cv::Point2f level_pt = kp.pt * static_cast<float>(1.0 / s);
    const cv::Mat& level = orb.pyramid()[kp.octave];
    EXPECT_NEAR(level_pt.x, std::round(level_pt.x), 1e-3);
    EXPECT_GE(level_pt.x, 19.0f - 1e-3f);
    EXPECT_GE(level_pt.y, 19.0f - 1e-3f);
    EXPECT_LE(level_pt.x, level.cols - 20 + 1e-3f);
    EXPECT_LE(level_pt.y, level.rows - 20 + 1e-3f);
    EXPECT_TRUE(kp.pt.x >= 0 && kp.pt.x < 640 && kp.pt.y >= 0 && kp.pt.y < 480);
    EXPECT_GE(kp.angle, 0.0f);
    EXPECT_LT(kp.angle, 360.0f);
    EXPECT_GT(kp.response, 0.0f);
  }
}

// Also with the levels split over two threads: the same output, bit for bit, on
// every call (the helper takes whichever level is next, so the split varies).
TEST(OrbExtractor, IsDeterministicWithOneOrTwoThreads) {
  const cv::Mat image = UniformTexture(3);
  OrbExtractor a(OrbConfig{}), b(OrbConfig{}), c(OrbConfig{});
  c.set_threads(2);
  EXPECT_EQ(c.threads(), 2);
  const Extraction e1 = ExtractAll(a, image), e2 = ExtractAll(a, image), e3 = ExtractAll(b, image);
  const Extraction e4 = ExtractAll(c, image), e5 = ExtractAll(c, image);
  for (const Extraction* e : {&e2, &e3, &e4, &e5}) {
    ASSERT_EQ(e1.kps.size(), e->kps.size());
    for (size_t i = 0; i < e1.kps.size(); ++i) {
      EXPECT_EQ(e1.kps[i].pt, e->kps[i].pt);
      EXPECT_EQ(e1.kps[i].angle, e->kps[i].angle);
      EXPECT_EQ(e1.kps[i].octave, e->kps[i].octave);
      EXPECT_EQ(e1.kps[i].response, e->kps[i].response);
    }
    EXPECT_EQ(cv::norm(e1.desc, e->desc, cv::NORM_HAMMING), 0.0);
  }
}

TEST(OrbExtractor, HandlesImagesWithoutCornersOrTooSmall) {
  OrbExtractor orb(OrbConfig{});
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  orb.Extract(cv::Mat(480, 640, CV_8UC1, cv::Scalar(90)), kps, desc);
  EXPECT_TRUE(kps.empty());
  EXPECT_EQ(desc.rows, 0);
  orb.Extract(UniformTexture(4, {30, 30}), kps, desc);
  EXPECT_TRUE(kps.empty());
  EXPECT_EQ(desc.rows, 0);
}

// Two consecutive TUM fr1/rpy frames (33 ms apart, but a fast, blurred
// rotation of ~40 px): the full budget on a real room, and enough mutual
// descriptor matches that agree with one homography (the motion is nearly a
// pure rotation). OpenCV's own ORB scores about the same on this pair.
TEST(OrbExtractor, RealFramesGiveRepeatableFeatures) {
  SGSLAM_REQUIRE_SHARED(rgb, "data/tum_fr1_rpy/rgb");
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(rgb)) files.push_back(entry.path());
  ASSERT_GE(files.size(), 2u);
  std::sort(files.begin(), files.end());
  OrbExtractor orb(OrbConfig{});
  Extraction e[2];
  for (int i = 0; i < 2; ++i) {
    const cv::Mat gray = cv::imread(files[static_cast<size_t>(i)].string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(gray.empty()) << files[static_cast<size_t>(i)];
    e[i] = ExtractAll(orb, gray);
    EXPECT_GE(e[i].kps.size(), 900u);
  }
  std::vector<cv::DMatch> matches;
  cv::BFMatcher(cv::NORM_HAMMING, /*crossCheck=*/true).match(e[0].desc, e[1].desc, matches);
  std::vector<cv::Point2f> p0, p1;
  for (const cv::DMatch& m : matches) {
    if (m.distance > 50) continue;
    p0.push_back(e[0].kps[static_cast<size_t>(m.queryIdx)].pt);
    p1.push_back(e[1].kps[static_cast<size_t>(m.trainIdx)].pt);
  }
  ASSERT_GE(p0.size(), 200u);
  cv::Mat inliers;
  cv::findHomography(p0, p1, cv::RANSAC, 3.0, inliers, 2000, 0.999);
  RecordProperty("matches", static_cast<int>(p0.size()));
  RecordProperty("homography_inliers", cv::countNonZero(inliers));
  EXPECT_GE(cv::countNonZero(inliers), 80);
}

}  // namespace
}  // namespace sgslam::features
