#include "sgslam/map/map.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

#include "sgslam/map/map_check.h"

namespace sgslam {
namespace {

std::uint64_t kf_frame_id(const Map& map) { return map.keyframes().size(); }

// A keyframe of n keypoints on a grid, all with depth 2 m and random descriptors.
std::shared_ptr<KeyFrame> MakeKeyFrame(Map& map, std::size_t n, double x) {
  static const auto camera = std::make_shared<Camera>(CameraConfig{});
  static const auto scale = std::make_shared<ScaleLevels>(features::MakeScaleLevels(1.2, 8));
  std::mt19937 rng(static_cast<unsigned>(map.keyframes().size() + 1));
  std::vector<cv::KeyPoint> keys;
  for (std::size_t i = 0; i < n; ++i) keys.emplace_back(20.f + 10.f * (i % 50), 20.f + 10.f * (i / 50), 31.f, 0.f, 50.f, 0);
  cv::Mat desc(static_cast<int>(n), 32, CV_8U);
  cv::randu(desc, 0, 256);
  cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(10000));
  auto f = MakeFeatures(keys, desc, depth, camera, scale);
  SE3 T_c_w(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-x, 0, 0));
  auto kf = std::make_shared<KeyFrame>(map.NewKeyFrameId(), kf_frame_id(map), 0, f, T_c_w);
  map.AddKeyFrame(kf);
  return kf;
}

std::shared_ptr<MapPoint> Observe(Map& map, const std::vector<std::pair<std::shared_ptr<KeyFrame>, std::size_t>>& views) {
  auto p = std::make_shared<MapPoint>(map.NewMapPointId(), Eigen::Vector3d(0, 0, 2), views.front().first);
  for (const auto& [kf, i] : views) {
    p->AddObservation(kf, i);
    kf->SetMapPoint(i, p);
  }
  p->UpdateDescriptor();
  p->UpdateNormalAndDepth();
  map.AddMapPoint(p);
  return p;
}

TEST(Map, ConnectionsCountSharedPointsAndBuildTheTree) {
  Map map;
  auto a = MakeKeyFrame(map, 100, 0), b = MakeKeyFrame(map, 100, 0.1), c = MakeKeyFrame(map, 100, 0.2);
  for (std::size_t i = 0; i < 40; ++i) Observe(map, {{a, i}, {b, i}});
  for (std::size_t i = 40; i < 60; ++i) Observe(map, {{a, i}, {b, i}, {c, i}});
  for (const auto& kf : {a, b, c}) kf->UpdateConnections();
  EXPECT_EQ(a->Weight(b->id), 60);
  EXPECT_EQ(b->Weight(c->id), 20);
  EXPECT_EQ(a->Covisibles().front(), b);
  EXPECT_EQ(b->parent(), a);
  EXPECT_TRUE(c->parent() == a || c->parent() == b);
  EXPECT_TRUE(CheckMapConsistency(map).empty());
}

TEST(Map, CullingAKeyFrameKeepsTheMapConsistent) {
  Map map;
  auto a = MakeKeyFrame(map, 200, 0), b = MakeKeyFrame(map, 200, 0.1), c = MakeKeyFrame(map, 200, 0.2);
  for (std::size_t i = 0; i < 50; ++i) Observe(map, {{a, i}, {b, i}});          // lost with b
  for (std::size_t i = 50; i < 100; ++i) Observe(map, {{a, i}, {b, i}, {c, i}});  // survive
  for (std::size_t i = 100; i < 150; ++i) Observe(map, {{b, i}, {c, i}});        // lost with b
  for (const auto& kf : {a, b, c}) kf->UpdateConnections();
  c->SetParent(b);
  const std::size_t points_before = map.map_points().size();
  b->SetBad(map);
  EXPECT_TRUE(b->bad());
  EXPECT_FALSE(map.keyframes().count(b->id));
  EXPECT_EQ(c->parent(), a);  // re-attached to the candidate it shares points with
  EXPECT_EQ(b->parent_when_culled(), a);
  EXPECT_EQ(map.map_points().size(), points_before - 100);
  const auto problems = CheckMapConsistency(map);
  EXPECT_TRUE(problems.empty()) << problems.front();
  a->SetBad(map);  // the first keyframe anchors the map and is never culled
  EXPECT_FALSE(a->bad());
}

TEST(Map, ReplacingADuplicateMovesItsObservations) {
  Map map;
  auto a = MakeKeyFrame(map, 10, 0), b = MakeKeyFrame(map, 10, 0.1), c = MakeKeyFrame(map, 10, 0.2);
  auto p = Observe(map, {{a, 1}, {b, 2}});
  auto q = Observe(map, {{b, 3}, {c, 4}});
  p->ReplaceWith(q, map);
  EXPECT_TRUE(p->bad());
  EXPECT_EQ(p->replaced(), q);
  EXPECT_EQ(a->map_point(1), q);
  EXPECT_EQ(b->map_point(2), nullptr);  // q was already seen in b: keep its association
  EXPECT_EQ(q->observations().size(), 3u);
  EXPECT_EQ(q->num_observations(), 6);  // depth observations count twice
  EXPECT_TRUE(CheckMapConsistency(map).empty());
}

// Tracking corrects a keyframe's keypoints once more before local mapping sees it
// (Tracker::CorrectWaitingKeyFrame); its map points stay indexed by keypoint, so
// the keypoints must stay the same ones.
TEST(KeyFrame, ReplacedFeaturesMustKeepTheKeypoints) {
  Map map;
  const auto kf = MakeKeyFrame(map, 20, 0.0);
  const auto other = MakeKeyFrame(map, 21, 0.0);
  const auto same = MakeKeyFrame(map, 20, 0.5);
  EXPECT_THROW(kf->ReplaceFeatures(other->features), std::invalid_argument);
  EXPECT_THROW(kf->ReplaceFeatures(nullptr), std::invalid_argument);
  kf->ReplaceFeatures(same->features);
  EXPECT_EQ(kf->features, same->features);
}

TEST(MapPoint, PredictScaleFollowsDistance) {
  Map map;
  auto a = MakeKeyFrame(map, 10, 0);
  auto p = Observe(map, {{a, 0}});
  const ScaleLevels scale = features::MakeScaleLevels(1.2, 8);
  EXPECT_EQ(p->PredictScale(2.0, scale), 0);       // as observed, at level 0
  EXPECT_EQ(p->PredictScale(2.0 / 1.2, scale), 1);  // closer: coarser level
  EXPECT_EQ(p->PredictScale(0.1, scale), 7);        // clamped
  EXPECT_NEAR(p->normal().z(), 1.0, 1e-12);
}

}  // namespace
}  // namespace sgslam
