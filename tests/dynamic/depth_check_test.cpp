// The RGB-D motion check: a previous point lifted with its depth, moved by the
// camera motion, compared with the current depth and keypoint.
#include <gtest/gtest.h>

#include "sgslam/dynamic/depth_check.h"

namespace sgslam::dynamic {
namespace {

constexpr double kFx = 525, kCx = 319.5, kCy = 239.5;

struct Scene {
  DepthCheckInput in;
  std::vector<cv::Point2f> prev, cur;
};

// A fronto-parallel wall at 2.5 m seen before and after a 2 cm sideways step, and
// three points on it: static, moved sideways 5 cm, moved 15 cm towards the camera.
Scene Make(int depth_type) {
  Scene s;
  s.in.K = {kFx, kFx, kCx, kCy};
  Vector6d xi;
  xi << -0.02, 0, 0, 0, 0, 0;
  s.in.T_cur_prev = SE3::Exp(xi);  // the camera moved +2 cm along x
  const double wall = 2.5;
  auto image = [&](double z) {
    cv::Mat m(480, 640, CV_32F, cv::Scalar(z));
    if (depth_type == CV_32F) return m;
    cv::Mat raw;
    m.convertTo(raw, CV_16U, s.in.depth_factor);
    return raw;
  };
  s.in.prev_depth = image(wall);
  s.in.cur_depth = image(wall);
  auto project = [&](const Eigen::Vector3d& X) {
    return cv::Point2f(static_cast<float>(kFx * X.x() / X.z() + kCx), static_cast<float>(kFx * X.y() / X.z() + kCy));
  };
  const Eigen::Vector3d P[3] = {{-0.5, 0.1, wall}, {0.2, -0.2, wall}, {0.6, 0.3, wall}};
  const Eigen::Vector3d motion[3] = {{0, 0, 0}, {0.05, 0, 0}, {0, 0, -0.15}};
  for (int i = 0; i < 3; ++i) {
    s.prev.push_back(project(P[i]));
    s.cur.push_back(project(s.in.T_cur_prev * (P[i] + motion[i])));
  }
  // The point that came closer is seen at its new depth in the current frame.
  const cv::Point c = s.cur[2];
  cv::Mat roi = s.in.cur_depth(cv::Rect(c.x - 3, c.y - 3, 7, 7));
  if (depth_type == CV_32F)
    roi.setTo(wall - 0.15);
  else
    roi.setTo(cvRound((wall - 0.15) * s.in.depth_factor));
  return s;
}

TEST(DepthCheck, FlagsSidewaysAndDepthMotionAndKeepsStaticPoints) {
  for (int type : {CV_32F, CV_16U}) {
    const Scene s = Make(type);
    const std::vector<DepthResidual> r = CheckDepth(s.prev, s.cur, {true, true, true}, s.in);
    ASSERT_EQ(r.size(), 3u);
    for (const DepthResidual& x : r) EXPECT_TRUE(x.valid);
    EXPECT_FALSE(r[0].moved);
    EXPECT_LT(r[0].reprojection_error, 0.01);
    EXPECT_LT(r[0].depth_error, 1e-3);
    EXPECT_TRUE(r[1].moved);  // 5 cm sideways at 2.5 m: 10.5 px, no depth change
    EXPECT_NEAR(r[1].reprojection_error, kFx * 0.05 / 2.5, 0.1);
    EXPECT_LT(r[1].depth_error, 1e-3);
    EXPECT_TRUE(r[2].moved);  // 15 cm closer
    EXPECT_NEAR(r[2].depth_error, 0.15, 1e-3);
  }
}

// A static point whose previous pixel holds another surface's depth (a depth edge
// one pixel off, fr1's depth-to-colour offset): lifted with it, the point is 1.5 m
// off and 6 px away after the 2 cm step. The window of previous depths finds the
// wall's depth next to it; the movers stay flagged.
TEST(DepthCheck, WindowOfPreviousDepthsForgivesADepthEdgeOnePixelOff) {
  Scene s = Make(CV_32F);
  const cv::Point p = s.prev[0];
  s.in.prev_depth.at<float>(p.y, p.x) = 1.0f;
  DepthCheckParams params;
  params.window = 0;
  const std::vector<DepthResidual> centre = CheckDepth(s.prev, s.cur, {true, true, true}, s.in, params);
  EXPECT_TRUE(centre[0].moved);
  params.window = 1;  // kDepthCheckWindow
  const std::vector<DepthResidual> window = CheckDepth(s.prev, s.cur, {true, true, true}, s.in, params);
  EXPECT_FALSE(window[0].moved);
  EXPECT_LT(window[0].reprojection_error, 0.01);
  EXPECT_TRUE(window[1].moved);
  EXPECT_TRUE(window[2].moved);
}

// Fast rotation with a rolling shutter: every static point lands 4 px off where the
// motion puts it; a mover lands 25 px off. A fixed 3 px tolerance flags them all, a
// tolerance of 3x the frame's median residual only the mover.
TEST(DepthCheck, ReprojectionToleranceFollowsTheFramesMedianResidual) {
  DepthCheckInput in;
  in.K = {kFx, kFx, kCx, kCy};
  in.prev_depth = cv::Mat(480, 640, CV_32F, cv::Scalar(2.0));
  in.cur_depth = in.prev_depth.clone();
  std::vector<cv::Point2f> prev, cur;
  for (int i = 0; i < 20; ++i) {
    prev.emplace_back(100.f + 20.f * i, 100.f + 10.f * i);
    cur.push_back(prev.back() + cv::Point2f(4.f, 0.f));
  }
  prev.emplace_back(320.f, 400.f);
  cur.push_back(prev.back() + cv::Point2f(25.f, 0.f));
  const std::vector<bool> use(prev.size(), true);
  DepthCheckParams c;
  c.reprojection_median_factor = 0;
  std::vector<DepthResidual> r = CheckDepth(prev, cur, use, in, c);
  for (const DepthResidual& x : r) EXPECT_TRUE(x.valid && x.moved);
  c.reprojection_median_factor = 3;  // kReprojectionMedianFactor, over the fixed 3 px (kReprojectionTolerance)
  r = CheckDepth(prev, cur, use, in, c);
  for (size_t i = 0; i + 1 < r.size(); ++i) EXPECT_FALSE(r[i].moved) << i;
  EXPECT_TRUE(r.back().moved);
  // The fixed tolerance stays the floor: with every residual tiny, 3x the median is
  // below 3 px and a 5 px outlier is still flagged.
  for (size_t i = 0; i + 1 < cur.size(); ++i) cur[i] = prev[i] + cv::Point2f(0.2f, 0.f);
  cur.back() = prev.back() + cv::Point2f(5.f, 0.f);
  r = CheckDepth(prev, cur, use, in, c);
  for (size_t i = 0; i + 1 < r.size(); ++i) EXPECT_FALSE(r[i].moved) << i;
  EXPECT_TRUE(r.back().moved);
}

TEST(DepthCheck, SkipsMissingDepthAndUnusedPairs) {
  Scene s = Make(CV_32F);
  s.in.prev_depth.at<float>(cvRound(s.prev[0].y), cvRound(s.prev[0].x)) = 0;
  const std::vector<DepthResidual> r = CheckDepth(s.prev, s.cur, {true, false, true}, s.in);
  EXPECT_FALSE(r[0].valid);
  EXPECT_FALSE(r[1].valid);
  EXPECT_TRUE(r[2].valid && r[2].moved);
}

// The tolerances a residual was judged with are reported (DepthCheckParams::
// confirm_static compares against them); without a reprojection test nothing limits
// that error.
TEST(DepthCheck, ReportsTheTolerancesItUsed) {
  const Scene s = Make(CV_32F);
  DepthCheckParams c;
  std::vector<DepthResidual> r = CheckDepth(s.prev, s.cur, {true, true, true}, s.in, c);
  EXPECT_NEAR(r[0].depth_tolerance, kDepthTolerance + kDepthToleranceQuadratic * 2.5 * 2.5, 1e-6);
  EXPECT_DOUBLE_EQ(r[0].reprojection_tolerance, kReprojectionTolerance);  // three points: no median level
  c.reprojection_tolerance = 0;
  r = CheckDepth(s.prev, s.cur, {true, true, true}, s.in, c);
  EXPECT_TRUE(std::isinf(r[0].reprojection_tolerance));
  EXPECT_FALSE(r[1].moved);  // sideways only: no depth change, and no reprojection test
}

TEST(DepthCheck, UndistortFunctionIsAppliedToBothPoints) {
  Scene s = Make(CV_32F);
  // Points given shifted by +5 px, undistort removes the shift: same verdicts.
  for (auto* v : {&s.prev, &s.cur}) {
    for (cv::Point2f& p : *v) p.x += 5;
  }
  s.in.undistort = [](const Eigen::Vector2d& p) { return Eigen::Vector2d(p.x() - 5, p.y()); };
  const std::vector<DepthResidual> r = CheckDepth(s.prev, s.cur, {true, true, true}, s.in);
  EXPECT_FALSE(r[0].moved);
  EXPECT_LT(r[0].reprojection_error, 0.01);
  EXPECT_TRUE(r[1].moved);
}

}  // namespace
}  // namespace sgslam::dynamic
