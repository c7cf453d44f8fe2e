// UnjudgedAmongMovers (neighbours.h): an unjudged keypoint is taken as moving only
// when most of its judged neighbours were rejected.
#include <gtest/gtest.h>

#include "sgslam/dynamic/neighbours.h"

namespace sgslam::dynamic {
namespace {

KeypointVerdict Verdict(bool kept, Why why) {
  KeypointVerdict v;
  v.kept = kept;
  v.why = why;
  return v;
}

TEST(Neighbours, UnjudgedAmongRejectedIsFlaggedAmongKeptIsNot) {
  std::vector<cv::KeyPoint> keys;
  std::vector<KeypointVerdict> v;
  // A mover at x = 100: three keypoints rejected by geometry or depth, one unjudged.
  for (float dx : {-5.f, 0.f, 5.f}) keys.emplace_back(cv::Point2f(100 + dx, 100), 31.f);
  v = {Verdict(false, Why::kGeometry), Verdict(false, Why::kDepth), Verdict(false, Why::kGeometry)};
  keys.emplace_back(cv::Point2f(102, 104), 31.f);
  v.push_back(Verdict(true, Why::kUnjudged));
  // Static ground at x = 300: three kept keypoints and one unjudged.
  for (float dx : {-5.f, 0.f, 5.f}) keys.emplace_back(cv::Point2f(300 + dx, 100), 31.f), v.push_back(Verdict(true, Why::kStatic));
  keys.emplace_back(cv::Point2f(302, 104), 31.f);
  v.push_back(Verdict(true, Why::kUnjudged));
  // An unjudged keypoint alone, and one next to a single rejected keypoint.
  keys.emplace_back(cv::Point2f(500, 400), 31.f), v.push_back(Verdict(true, Why::kUnjudged));
  keys.emplace_back(cv::Point2f(500, 200), 31.f), v.push_back(Verdict(false, Why::kDepth));
  keys.emplace_back(cv::Point2f(505, 200), 31.f), v.push_back(Verdict(true, Why::kUnjudged));

  const std::vector<std::size_t> flagged = UnjudgedAmongMovers(keys, v, 20.0, 0.5, 2);
  EXPECT_EQ(flagged, std::vector<std::size_t>{3});
  EXPECT_TRUE(UnjudgedAmongMovers(keys, v, 0.0, 0.5, 2).empty());  // radius 0: off
  EXPECT_EQ(UnjudgedAmongMovers(keys, v, 20.0, 0.5, 1), (std::vector<std::size_t>{3, 10}));
}

}  // namespace
}  // namespace sgslam::dynamic
