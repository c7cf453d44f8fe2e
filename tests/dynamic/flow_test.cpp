// Algorithm 1 lines 1-2: backward LK flow and the pair filters.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "sgslam/dynamic/flow.h"

namespace sgslam::dynamic {
namespace {

// Smooth random texture (blurred noise), 640x480.
cv::Mat Texture(int seed) {
  cv::Mat noise(480, 640, CV_8U);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 2.0);
  cv::normalize(noise, noise, 20, 220, cv::NORM_MINMAX);  // headroom: no saturation under +-20
  return noise;
}

// prev(x) = cur(x - shift): a point at p in the current image was at p + shift before.
cv::Mat Shifted(const cv::Mat& image, cv::Point2f shift) {
  const cv::Mat M = (cv::Mat_<double>(2, 3) << 1, 0, shift.x, 0, 1, shift.y);
  cv::Mat out;
  cv::warpAffine(image, out, M, image.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  return out;
}

std::vector<cv::Point2f> Grid(int step, int margin) {
  std::vector<cv::Point2f> p;
  for (int y = margin; y < 480 - margin; y += step) {
    for (int x = margin; x < 640 - margin; x += step)
      p.emplace_back(static_cast<float>(x) + 0.3f, static_cast<float>(y) + 0.6f);
  }
  return p;
}

TEST(Flow, TracksCurrentPointsBackIntoThePreviousImage) {
  const cv::Mat cur = Texture(1);
  const cv::Point2f shift(3.4f, -2.2f);
  const cv::Mat prev = Shifted(cur, shift);
  const std::vector<cv::Point2f> pts = Grid(40, 40);
  const FlowPairs f = TrackBackward(FlowFrame{prev, {}}, FlowFrame{cur, {}}, pts);
  EXPECT_EQ(f.valid, static_cast<int>(pts.size()));
  for (size_t i = 0; i < pts.size(); ++i) {
    EXPECT_NEAR(f.prev[i].x, pts[i].x + shift.x, 0.05);
    EXPECT_NEAR(f.prev[i].y, pts[i].y + shift.y, 0.05);
  }
}

TEST(Flow, PrebuiltPyramidsGiveTheSameResult) {
  const cv::Mat cur = Texture(2), prev = Shifted(cur, {1.5f, 0.7f});
  const std::vector<cv::Point2f> pts = Grid(23, 5);
  const FlowPairs a = TrackBackward(FlowFrame{prev, {}}, FlowFrame{cur, {}}, pts);
  const FlowPairs b = TrackBackward(FlowFrame{prev, BuildFlowPyramid(prev)}, FlowFrame{cur, BuildFlowPyramid(cur)}, pts);
  ASSERT_EQ(a.prev.size(), b.prev.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    EXPECT_EQ(a.status[i], b.status[i]);
    EXPECT_NEAR(a.prev[i].x, b.prev[i].x, 1e-4);
    EXPECT_NEAR(a.prev[i].y, b.prev[i].y, 1e-4);
  }
}

TEST(Flow, DropsBorderAndChangedAppearance) {
  const cv::Mat cur = Texture(3);
  cv::Mat prev = Shifted(cur, {2.0f, 1.0f});
  // A region of the previous image repainted with unrelated texture (occlusion) and
  // a region with an exposure change only (must stay).
  Texture(4)(cv::Rect(300, 200, 60, 60)).copyTo(prev(cv::Rect(300, 200, 60, 60)));
  prev(cv::Rect(100, 300, 80, 80)) += cv::Scalar(25);
  const std::vector<cv::Point2f> pts = {{3.f, 240.f}, {636.f, 100.f}, {330.f, 230.f}, {140.f, 340.f}, {500.f, 100.f}};
  const FlowPairs f = TrackBackward(FlowFrame{prev, {}}, FlowFrame{cur, {}}, pts);
  EXPECT_EQ(f.status[0], PairStatus::kBorder);
  EXPECT_EQ(f.status[1], PairStatus::kBorder);
  EXPECT_TRUE(f.status[2] == PairStatus::kAppearance || f.status[2] == PairStatus::kFlowFailed);
  EXPECT_EQ(f.status[3], PairStatus::kOk);
  EXPECT_EQ(f.status[4], PairStatus::kOk);
  EXPECT_EQ(f.valid, 2);
}

TEST(Flow, PatchDifferenceIgnoresExposure) {
  const cv::Mat a = Texture(5);
  cv::Mat b = a + cv::Scalar(20);
  EXPECT_NEAR(PatchDifference(a, {200.f, 200.f}, b, {200.f, 200.f}, 2), 0.0, 1e-3);
  EXPECT_GT(PatchDifference(a, {200.f, 200.f}, a, {260.f, 150.f}, 2), 5.0);  // another place
}

}  // namespace
}  // namespace sgslam::dynamic
