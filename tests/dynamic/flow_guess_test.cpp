// LK's starting point from the motion model (flow_guess.h) and the flow from it.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

#include "sgslam/dynamic/flow.h"
#include "sgslam/dynamic/flow_guess.h"

namespace sgslam::dynamic {
namespace {

const Pinhole kK{517.3, 516.5, 318.6, 255.3};

cv::Point2f Project(const Eigen::Vector3d& X) {
  return {static_cast<float>(kK.fx * X.x() / X.z() + kK.cx), static_cast<float>(kK.fy * X.y() / X.z() + kK.cy)};
}

TEST(FlowGuess, PredictsWhereStaticPointsWereInThePreviousImage) {
  // Points in the previous camera, seen again after a known motion; the current
  // depth image holds each point's depth at its (rounded) pixel only.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const SE3 T_cur_prev = SE3::Exp((Vector6d() << 0.03, -0.02, 0.01, 0.04, -0.05, 0.03).finished());
  cv::Mat depth(480, 640, CV_32F, cv::Scalar(0));
  std::vector<cv::Point2f> cur, expected;
  std::vector<double> z;
  while (cur.size() < 200) {
    const Eigen::Vector3d P(1.2 * u(rng), 0.9 * u(rng), 2.0 + 1.2 * u(rng));
    const Eigen::Vector3d X = T_cur_prev * P;
    const cv::Point2f c = Project(X), p = Project(P);
    if (c.x < 1 || c.y < 1 || c.x > 638 || c.y > 478 || depth.at<float>(cvRound(c.y), cvRound(c.x)) > 0) continue;
    depth.at<float>(cvRound(c.y), cvRound(c.x)) = static_cast<float>(X.z());
    cur.push_back(c), expected.push_back(p), z.push_back(X.z());
  }
  // A raw (distorted) position differs from the undistorted one by a small offset,
  // which the guess keeps.
  const cv::Point2f offset(1.5f, -0.5f);
  std::vector<cv::Point2f> raw(cur);
  for (cv::Point2f& r : raw) r += offset;
  // Raw positions index the depth image: shift it with them.
  cv::Mat depth_raw(depth.size(), CV_32F, cv::Scalar(0));
  for (std::size_t i = 0; i < raw.size(); ++i) depth_raw.at<float>(cvRound(raw[i].y), cvRound(raw[i].x)) = static_cast<float>(z[i]);
  const FlowPrediction prediction{depth_raw, 1.0, kK, T_cur_prev};
  const std::vector<cv::Point2f> guess = PredictPrevious(raw, cur, prediction, 0.2, 6.0);
  ASSERT_EQ(guess.size(), cur.size());
  for (std::size_t i = 0; i < cur.size(); ++i) {
    EXPECT_NEAR(guess[i].x, expected[i].x + offset.x, 1e-3) << i;
    EXPECT_NEAR(guess[i].y, expected[i].y + offset.y, 1e-3) << i;
  }
}

TEST(FlowGuess, APointWithoutDepthIsLiftedAtTheMedianDepthAndARotationNeedsNone) {
  // Under a pure rotation depth does not matter: every point, measured or not,
  // lands where the rotation puts it.
  const SE3 T_cur_prev = SE3::Exp((Vector6d() << 0, 0, 0, 0.02, -0.06, 0.01).finished());
  const cv::Mat depth(480, 640, CV_16U, cv::Scalar(0));  // no measurement at all: 2 m
  std::vector<cv::Point2f> cur;
  for (int y = 40; y < 480; y += 80) {
    for (int x = 40; x < 640; x += 80) cur.emplace_back(static_cast<float>(x), static_cast<float>(y));
  }
  const std::vector<cv::Point2f> guess = PredictPrevious(cur, cur, {depth, 5000, kK, T_cur_prev}, 0.2, 6.0);
  const SE3 T_prev_cur = T_cur_prev.Inverse();
  for (std::size_t i = 0; i < cur.size(); ++i) {
    const Eigen::Vector3d ray((cur[i].x - kK.cx) / kK.fx, (cur[i].y - kK.cy) / kK.fy, 1.0);
    const cv::Point2f p = Project(T_prev_cur * (7.0 * ray));  // any depth
    EXPECT_NEAR(guess[i].x, p.x, 1e-3);
    EXPECT_NEAR(guess[i].y, p.y, 1e-3);
  }
}

cv::Mat Texture(int seed) {
  cv::Mat noise(480, 640, CV_8U);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 2.0);
  cv::normalize(noise, noise, 20, 220, cv::NORM_MINMAX);
  return noise;
}

TEST(FlowGuess, AStartNearTheAnswerFindsAMotionBeyondTheWindowWithoutAPyramid) {
  // The image moved by 28 px, beyond the reach of a 21 px window on the full image
  // alone; started 2 px from the answer, the same LK finds every point.
  const cv::Mat cur = Texture(5);
  const cv::Point2f shift(28.0f, -9.0f);
  const cv::Mat M = (cv::Mat_<double>(2, 3) << 1, 0, shift.x, 0, 1, shift.y);
  cv::Mat prev;
  cv::warpAffine(cur, prev, M, cur.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  std::vector<cv::Point2f> pts, guess;
  for (int y = 60; y < 420; y += 30) {
    for (int x = 60; x < 580; x += 30) {
      pts.emplace_back(static_cast<float>(x) + 0.3f, static_cast<float>(y) + 0.6f);
      guess.push_back(pts.back() + shift + cv::Point2f(2.0f, -1.5f));
    }
  }
  DynamicConfig c;
  c.lk_levels = 0;
  c.lk_levels_predicted = 0;
  c.lk_probe = 0;  // the probe would track with lk_levels 0 as well, and fail
  const auto accurate = [&](const FlowPairs& f) {
    int n = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const cv::Point2f e = f.prev[i] - (pts[i] + shift);
      n += f.status[i] == PairStatus::kOk && std::hypot(e.x, e.y) < 0.05;
    }
    return n;
  };
  const int n = static_cast<int>(pts.size());
  EXPECT_EQ(accurate(TrackBackward(FlowFrame{prev, {}}, FlowFrame{cur, {}}, pts, c, &guess)), n);
  const int unguided = accurate(TrackBackward(FlowFrame{prev, {}}, FlowFrame{cur, {}}, pts, c));
  EXPECT_LT(unguided, n / 4);
  // lk_levels_predicted applies only with a start: without one, lk_levels' pyramid
  // does the work (on this fine texture its coarse levels are nearly flat, so not
  // for every point).
  c.lk_levels = 3;
  EXPECT_GT(accurate(TrackBackward(FlowFrame{prev, {}}, FlowFrame{cur, {}}, pts, c)), n / 2);

  // A prediction off by 12 px, beyond a level-0 window: alone it fails, the probe
  // (every n / lk_probe-th point tracked with the full pyramid) measures the error
  // and moves every start.
  std::vector<cv::Point2f> off(guess);
  for (cv::Point2f& p : off) p += cv::Point2f(10.0f, -6.5f);  // 12 px from the answer
  EXPECT_LT(accurate(TrackBackward(FlowFrame{prev, {}}, FlowFrame{cur, {}}, pts, c, &off)), n / 4);
  c.lk_probe = 20;
  EXPECT_EQ(accurate(TrackBackward(FlowFrame{prev, {}}, FlowFrame{cur, {}}, pts, c, &off)), n);
}

}  // namespace
}  // namespace sgslam::dynamic
