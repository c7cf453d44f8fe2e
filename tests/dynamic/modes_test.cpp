// The decision rules around Algorithm 1: regions and weights, keypoints without a
// pair, the fallback, determinism, prebuilt pyramids and the config checks.
#include <gtest/gtest.h>

#include "dynamic/dynamic_test_scene.h"
#include "sgslam/common/error.h"

namespace sgslam::dynamic {
namespace {

Detection Box(const std::string& name, float x, float y, float w, float h) { return {0, name, 1.f, {x, y, w, h}}; }

double Weight(const std::string& name) { return name == "person" ? 5 : name == "chair" ? 2 : 1; }

struct Fixture {
  test::FramePair pair = test::MakePair("walkers", 60);
  std::vector<cv::KeyPoint> keys = test::DetectKeypoints(pair.cur_gray);
};
const Fixture& Data() {
  static const Fixture f;
  return f;
}

TEST(Modes, LargestWeightOfTheBoxesHoldingAKeypointCounts) {
  const std::vector<cv::KeyPoint> keys = {{10, 10, 7}, {50, 50, 7}, {150, 150, 7}, {300, 300, 7}, {100, 100, 7}};
  const std::vector<Detection> dets = {Box("chair", 0, 0, 100, 100), Box("person", 40, 40, 100, 100),
                                       Box("tv", 250, 250, 100, 100)};
  EXPECT_EQ(KeypointWeights(keys, dets, Weight), (std::vector<double>{2, 5, 1, 1, 5}));
  EXPECT_EQ(KeypointWeights(keys, dets, {}), std::vector<double>(5, 1.0));
}

// A person at 2 m fills the middle of its box; the wall 4 m away shows beside it.
TEST(Modes, BackgroundBehindADynamicBoxKeepsTheStaticWeight) {
  cv::Mat with_depth(200, 200, CV_32F, cv::Scalar(4.f));
  with_depth(cv::Rect(70, 20, 60, 170)).setTo(2.f);  // the person, inside the box [50, 150) x [10, 190)
  cv::Mat depth = with_depth.clone();
  depth.at<float>(180, 52) = 0.f;  // a hole under the keypoint at (52, 180)
  const std::vector<Detection> dets = {Box("person", 50, 10, 100, 180), Box("chair", 0, 150, 60, 50)};
  // On the person; background left and right of it; background without depth; outside.
  const std::vector<cv::KeyPoint> keys = {{100, 100, 7}, {55, 100, 7}, {145, 30, 7}, {52, 180, 7}, {20, 20, 7}};
  EXPECT_NEAR(BoxObjectDepth(dets[0].box, depth, 1.0, 0.25), 2.0, 1e-6);
  EXPECT_EQ(KeypointWeightsWithDepth(keys, dets, Weight, depth, 1.0, 0.5), (std::vector<double>{5, 1, 1, 5, 1}));
  // With depth, the keypoint at (52, 180) is background of the person box, but the
  // chair box (w = 2) holds it too and the chair's own depth is 4 m: w = 2.
  EXPECT_EQ(KeypointWeightsWithDepth(keys, dets, Weight, with_depth, 1.0, 0.5), (std::vector<double>{5, 1, 1, 2, 1}));
  // Off (band 0), or a raw 16-bit depth image: the same as KeypointWeights / as metres.
  EXPECT_EQ(KeypointWeightsWithDepth(keys, dets, Weight, depth, 1.0, 0.0), KeypointWeights(keys, dets, Weight));
  cv::Mat raw;
  depth.convertTo(raw, CV_16U, 5000.0);
  EXPECT_EQ(KeypointWeightsWithDepth(keys, dets, Weight, raw, 5000.0, 0.5), (std::vector<double>{5, 1, 1, 5, 1}));
  // A box with no depth in its middle: no object depth, every keypoint keeps w.
  cv::Mat holes(200, 200, CV_32F, cv::Scalar(0.f));
  EXPECT_EQ(BoxObjectDepth(dets[0].box, holes, 1.0, 0.25), 0.0);
  EXPECT_EQ(KeypointWeightsWithDepth(keys, dets, Weight, holes, 1.0, 0.5), KeypointWeights(keys, dets, Weight));
}

TEST(Modes, KeypointsWithoutAPairAreRejectedOnlyInsideDynamicBoxes) {
  const Fixture& f = Data();
  std::vector<cv::KeyPoint> keys = f.keys;
  keys.emplace_back(2.f, 100.f, 7.f);  // on the border: no pair
  keys.emplace_back(2.f, 300.f, 7.f);
  const std::vector<Detection> dets = {Box("person", 0, 280, 40, 40)};
  const DynamicConfig c;
  const RejectionResult r = RejectDynamicFeatures(f.pair.prev_gray, f.pair.cur_gray, keys, dets, Weight, c);
  const KeypointVerdict &outside = r.keypoints[keys.size() - 2], &inside = r.keypoints[keys.size() - 1];
  EXPECT_EQ(outside.pair, PairStatus::kBorder);
  EXPECT_TRUE(std::isnan(outside.distance));
  EXPECT_TRUE(outside.kept);
  EXPECT_EQ(outside.why, Why::kUnjudged);
  EXPECT_FALSE(inside.kept);
  EXPECT_EQ(inside.why, Why::kSemantics);
}

TEST(Modes, FallbackRelaxesThenRestoresTheMostStaticLooking) {
  const Fixture& f = Data();
  const std::vector<Detection> everywhere = {Box("person", 0, 0, 640, 480)};
  DynamicConfig c;
  c.eps_std = 1.0;  // d * 5 < 1 inside the image-wide box: most keypoints fail, the fallback has work
  Algorithm1Params p;
  p.flow.max_patch_difference = 12.0;
  p.fallback.min_kept_ratio = 0.9;
  RejectionResult r = RejectDynamicFeatures(f.pair.prev_gray, f.pair.cur_gray, f.keys, everywhere, Weight, c, p);
  const int min_kept = static_cast<int>(std::ceil(0.9 * static_cast<double>(f.keys.size())));
  EXPECT_GE(r.relax_steps, 1);
  EXPECT_DOUBLE_EQ(r.eps_used, c.eps_std * std::pow(p.fallback.relax_factor, r.relax_steps));
  EXPECT_GE(r.kept, min_kept);
  // Switched off (dynamic.refinements.fallback): no relaxation, nothing restored.
  c.refinements.fallback = false;
  r = RejectDynamicFeatures(f.pair.prev_gray, f.pair.cur_gray, f.keys, everywhere, Weight, c, p);
  EXPECT_EQ(r.relax_steps, 0);
  EXPECT_EQ(r.restored, 0);
  EXPECT_LT(r.kept, min_kept);
  c.refinements.fallback = true;
  // No relaxation: the restored keypoints are those with the smallest d * w.
  p.fallback.relax_steps = 0;
  p.fallback.min_kept_ratio = 0.5;
  r = RejectDynamicFeatures(f.pair.prev_gray, f.pair.cur_gray, f.keys, everywhere, Weight, c, p);
  EXPECT_GT(r.restored, 0);
  EXPECT_EQ(r.kept, static_cast<int>(std::ceil(0.5 * static_cast<double>(f.keys.size()))));
  double worst_kept = 0, best_rejected = 1e9;
  for (const KeypointVerdict& v : r.keypoints) {
    if (std::isnan(v.distance)) continue;
    if (v.kept)
      worst_kept = std::max(worst_kept, v.distance);
    else
      best_rejected = std::min(best_rejected, v.distance);
  }
  EXPECT_LE(worst_kept, best_rejected);
  // Semantic mode has no distance to rank by: it restores all, like the release.
  c.mode = "semantic";
  r = RejectDynamicFeatures(f.pair.prev_gray, f.pair.cur_gray, f.keys, everywhere, Weight, c, p);
  EXPECT_EQ(r.kept, static_cast<int>(f.keys.size()));
  EXPECT_EQ(r.restored, static_cast<int>(f.keys.size()));
}

TEST(Modes, TwoRunsAreIdenticalAndPyramidsChangeNothing) {
  const Fixture& f = Data();
  const DynamicConfig c;
  const auto a = RejectDynamicFeatures(f.pair.prev_gray, f.pair.cur_gray, f.keys, f.pair.detections, Weight, c);
  const auto b = RejectDynamicFeatures(f.pair.prev_gray, f.pair.cur_gray, f.keys, f.pair.detections, Weight, c);
  const auto p = RejectDynamicFeatures(FlowFrame{f.pair.prev_gray, BuildFlowPyramid(f.pair.prev_gray)},
                                       FlowFrame{f.pair.cur_gray, BuildFlowPyramid(f.pair.cur_gray)}, f.keys,
                                       f.pair.detections, Weight, c);
  ASSERT_TRUE(a.fundamental && b.fundamental && p.fundamental);
  EXPECT_EQ(a.fundamental->F_cur_prev, b.fundamental->F_cur_prev);
  int same_as_pyramid = 0;
  for (size_t i = 0; i < f.keys.size(); ++i) {
    EXPECT_EQ(a.keypoints[i].kept, b.keypoints[i].kept);
    EXPECT_EQ(a.keypoints[i].why, b.keypoints[i].why);
    EXPECT_TRUE(a.keypoints[i].distance == b.keypoints[i].distance ||
                (std::isnan(a.keypoints[i].distance) && std::isnan(b.keypoints[i].distance)));
    same_as_pyramid += a.keypoints[i].kept == p.keypoints[i].kept;
  }
  EXPECT_GE(same_as_pyramid, static_cast<int>(f.keys.size()) - 2);
  EXPECT_EQ(a.kept + a.rejected_geometry + a.rejected_semantics, static_cast<int>(f.keys.size()));
}

TEST(Modes, ConfigChecksAndModeNames) {
  ConfigChecker ok("dynamic");
  DynamicConfig{}.Validate(ok);
  EXPECT_TRUE(ok.problems().empty());
  DynamicConfig bad;
  bad.mode = "semantics";
  bad.eps_std = 0;
  ConfigChecker c("dynamic");
  bad.Validate(c);
  ASSERT_EQ(c.problems().size(), 2u);
  EXPECT_NE(c.problems()[0].find("dynamic.mode = semantics"), std::string::npos);
  EXPECT_THROW(ParseMode("semantics"), ConfigError);
  EXPECT_EQ(ParseMode("sg"), Mode::kSg);
}

// Rendered static room: pairs whose LK match agrees with the ground truth (within
// 0.5 px of the reprojection through the true depth and pose) lie within 1 px of
// their epipolar lines.
TEST(Epipolar, CorrectPairsOfAStaticSceneAreWithinOnePixel) {
  const test::FramePair p = test::MakePair("static", 40);
  const std::vector<cv::KeyPoint> keys = test::DetectKeypoints(p.cur_gray);
  DynamicConfig c;
  c.mode = "geometric";
  const RejectionResult r = RejectDynamicFeatures(p.prev_gray, p.cur_gray, keys, {}, {}, c);
  ASSERT_TRUE(r.fundamental);
  const SE3 T_prev_cur = p.T_cur_prev.Inverse();
  std::vector<double> d;
  for (size_t i = 0; i < keys.size(); ++i) {
    const KeypointVerdict& v = r.keypoints[i];
    const float z = p.cur_depth.at<float>(cvRound(keys[i].pt.y), cvRound(keys[i].pt.x));
    if (v.pair != PairStatus::kOk || z <= 0) continue;
    const Eigen::Vector3d X((keys[i].pt.x - p.K.cx) / p.K.fx * z, (keys[i].pt.y - p.K.cy) / p.K.fy * z, z);
    const Eigen::Vector3d Xp = T_prev_cur * X;
    const Eigen::Vector2d expected(p.K.fx * Xp.x() / Xp.z() + p.K.cx, p.K.fy * Xp.y() / Xp.z() + p.K.cy);
    if ((expected - Eigen::Vector2d(v.prev.x, v.prev.y)).norm() < 0.5) d.push_back(v.distance);
  }
  ASSERT_GT(d.size(), 500u);
  std::sort(d.begin(), d.end());
  std::printf("static pairs: %zu correct, epipolar distance median %.3f, p99 %.3f, max %.3f px\n", d.size(),
              d[d.size() / 2], d[d.size() * 99 / 100], d.back());
  EXPECT_LT(d.back(), 1.0);
  EXPECT_LT(d[d.size() / 2], 0.25);
}

}  // namespace
}  // namespace sgslam::dynamic
