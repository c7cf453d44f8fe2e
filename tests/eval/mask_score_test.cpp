// Rejection scored against ground-truth masks (eval/mask_score.h).
#include <gtest/gtest.h>

#include "sgslam/eval/mask_score.h"

namespace sgslam::eval {
namespace {

TEST(MaskScore, CountsMovingAndStaticKeypointsAndThoseNextToAMover) {
  cv::Mat mask(100, 100, CV_8U, cv::Scalar(0));
  mask(cv::Rect(40, 40, 20, 20)).setTo(255);  // a mover at x, y in [40, 60)
  const std::vector<cv::Point2f> points = {
      {50, 50}, {45, 55},    // moving: one rejected, one kept
      {36, 50}, {50, 63.2f}, // static, 4 and 4.2 px from the mover: one rejected, one kept
      {10, 10}, {90, 90}, {80, 20},  // static, far: one rejected
      {-1, 5}};              // outside the image: not scored
  const std::vector<std::uint8_t> rejected = {1, 0, 1, 0, 1, 0, 0, 1};
  const MaskScore s = ScoreKeypoints(mask, points, rejected);
  EXPECT_EQ(s.moving, 2u);
  EXPECT_EQ(s.moving_rejected, 1u);
  EXPECT_EQ(s.static_points, 5u);
  EXPECT_EQ(s.static_rejected, 2u);
  EXPECT_EQ(s.static_near, 2u);
  EXPECT_EQ(s.static_near_rejected, 1u);
  EXPECT_DOUBLE_EQ(s.static_loss(), 2.0 / 5.0);
  EXPECT_DOUBLE_EQ(s.static_loss_away(), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.recall(), 0.5);
  EXPECT_DOUBLE_EQ(s.precision(), 1.0 / 3.0);

  // Without a mover every static keypoint is away from movers.
  const MaskScore none = ScoreKeypoints(cv::Mat(100, 100, CV_8U, cv::Scalar(0)), points, rejected);
  EXPECT_EQ(none.static_near, 0u);
  EXPECT_EQ(none.static_points, 7u);
  EXPECT_DOUBLE_EQ(none.static_loss_away(), none.static_loss());

  MaskScore sum = s;
  sum.Add(none);
  EXPECT_EQ(sum.static_near, 2u);
  EXPECT_EQ(sum.static_points, 12u);
  EXPECT_EQ(sum.frames, 2u);
}

}  // namespace
}  // namespace sgslam::eval
