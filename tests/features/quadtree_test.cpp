#include "sgslam/features/quadtree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace sgslam::features {
namespace {

cv::KeyPoint At(float x, float y, float response) { return cv::KeyPoint(cv::Point2f(x, y), 31.0f, -1, response); }

const cv::Rect2f kRegion(0, 0, 400, 300);

TEST(Quadtree, KeepsEverythingWhenBelowTarget) {
  const std::vector<cv::KeyPoint> kps = {At(10, 10, 1), At(200, 100, 2), At(390, 290, 3)};
  const auto out = DistributeQuadtree(kps, kRegion, 10);
  EXPECT_EQ(out.size(), 3u);
  EXPECT_TRUE(DistributeQuadtree(kps, kRegion, 0).empty());
  EXPECT_TRUE(DistributeQuadtree({}, kRegion, 10).empty());
}

TEST(Quadtree, KeepsTheStrongestOfAClusterAndIsolatedPoints) {
  std::vector<cv::KeyPoint> kps;
  for (int i = 0; i < 50; ++i)
    kps.push_back(At(20.0f + static_cast<float>(i % 7), 20.0f + static_cast<float>(i / 7), static_cast<float>(i)));
  kps.push_back(At(350, 50, 0.5f));
  kps.push_back(At(60, 250, 0.5f));
  kps.push_back(At(300, 280, 0.5f));
  const auto out = DistributeQuadtree(kps, kRegion, 4);
  ASSERT_EQ(out.size(), 4u);
  int isolated = 0;
  float cluster_best = -1;
  for (const auto& kp : out) {
    if (kp.response == 0.5f) {
      ++isolated;
    } else {
      cluster_best = kp.response;
    }
  }
  EXPECT_EQ(isolated, 3);
  EXPECT_EQ(cluster_best, 49.0f);  // the cluster's strongest corner
}

TEST(Quadtree, ReturnsExactlyTheTargetAndIsDeterministic) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> x(0, 399), y(0, 299), r(0, 100);
  std::vector<cv::KeyPoint> kps;
  for (int i = 0; i < 3000; ++i) kps.push_back(At(std::round(x(rng)), std::round(y(rng)), r(rng)));
  for (int target : {1, 7, 50, 217, 1000}) {
    const auto a = DistributeQuadtree(kps, kRegion, target);
    const auto b = DistributeQuadtree(kps, kRegion, target);
    ASSERT_EQ(a.size(), static_cast<size_t>(target));
    for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].pt, b[i].pt);
  }
}

TEST(Quadtree, TerminatesOnDuplicatePositions) {
  std::vector<cv::KeyPoint> kps(20, At(100, 100, 1));
  kps.push_back(At(101, 100, 2));
  const auto out = DistributeQuadtree(kps, kRegion, 10);
  EXPECT_EQ(out.size(), 2u);
}

TEST(Quadtree, WideRegionsGetSeveralRoots) {
  // A 4:1 strip: four roots, so a target of 4 gives one point per quarter.
  const cv::Rect2f strip(0, 0, 400, 100);
  std::vector<cv::KeyPoint> kps;
  for (int i = 0; i < 40; ++i) kps.push_back(At(5.0f + 10.0f * static_cast<float>(i), 50, static_cast<float>(i % 3)));
  const auto out = DistributeQuadtree(kps, strip, 4);
  ASSERT_EQ(out.size(), 4u);
  for (int q = 0; q < 4; ++q) {
    EXPECT_EQ(std::count_if(out.begin(), out.end(),
                            [&](const cv::KeyPoint& k) { return static_cast<int>(k.pt.x / 100) == q; }),
              1);
  }
}

}  // namespace
}  // namespace sgslam::features
