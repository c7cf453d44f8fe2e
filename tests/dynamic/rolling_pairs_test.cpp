// Flow pairs of a rolling-shutter camera (rolling_pairs.h): two views rendered row
// by row while the turn speeds up between them, so that the two images are bent
// differently. The previous frame's velocity is known, the current one's is fitted.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "sgslam/camera/rolling_shutter.h"
#include "sgslam/dynamic/motion.h"
#include "sgslam/dynamic/rolling_pairs.h"

namespace sgslam::dynamic {
namespace {

constexpr double kFx = 525, kFy = 525, kCx = 319.5, kCy = 239.5, kReadout = 0.03;
constexpr int kHeight = 480;

Eigen::Vector2d Project(const Eigen::Vector3d& X) { return {kFx * X.x() / X.z() + kCx, kFy * X.y() / X.z() + kCy}; }

// The raw pixel of a point given in a frame's middle-row camera, seen by the row
// that exposes it (row v sees from Exp(w tau(v)), tau from RowTimeOffset).
Eigen::Vector2d RenderRow(const Eigen::Vector3d& X_mid, const Eigen::Vector3d& w) {
  Eigen::Vector2d p = Project(X_mid);
  for (int k = 0; k < 20; ++k) p = Project(so3::Exp(-w * RowTimeOffset(p.y(), kHeight, kReadout)) * X_mid);
  return p;
}

struct Scene {
  PairSet pairs;
  std::vector<bool> moving;
  std::vector<Eigen::Vector3d> X_prev;  // in the previous middle-row camera
  cv::Mat prev_depth, cur_depth;        // CV_32F, m, at the raw pixels (each row camera's depth)
  SE3 T_cur_prev;                       // between the middle-row cameras
  Eigen::Vector3d w_prev{0.4, -1.1, 0.3}, w_cur{1.2, -1.7, 0.8};  // rad/s: the turn speeds up
};

Scene MakeScene(int n_static, int movers, unsigned seed = 5) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1), z(1, 5);
  Scene s;
  Vector6d xi;
  xi << 0.004, -0.003, 0.002, 0.02, -0.035, 0.012;
  s.T_cur_prev = SE3::Exp(xi);
  s.prev_depth = cv::Mat(kHeight, 640, CV_32F, cv::Scalar(0));
  s.cur_depth = cv::Mat(kHeight, 640, CV_32F, cv::Scalar(0));
  while (static_cast<int>(s.moving.size()) < n_static + movers) {
    const bool mover = static_cast<int>(s.moving.size()) >= n_static;
    // An integer raw previous pixel (the depth lookup rounds) and its row camera's depth.
    const cv::Point p0(30 + static_cast<int>(580 * u(rng)), 30 + static_cast<int>(420 * u(rng)));
    if (s.prev_depth.at<float>(p0) != 0) continue;
    const double depth = z(rng);
    const Eigen::Vector3d X_row((p0.x - kCx) / kFx * depth, (p0.y - kCy) / kFy * depth, depth);
    const Eigen::Vector3d X = so3::Exp(s.w_prev * RowTimeOffset(p0.y, kHeight, kReadout)) * X_row;
    const Eigen::Vector3d X_cur = s.T_cur_prev * (X + (mover ? Eigen::Vector3d(0.05, 0, 0) : Eigen::Vector3d::Zero()));
    const Eigen::Vector2d p1 = RenderRow(X_cur, s.w_cur);
    if (p1.x() < 10 || p1.y() < 10 || p1.x() > 630 || p1.y() > 470) continue;
    const cv::Point p1i(cvRound(p1.x()), cvRound(p1.y()));
    if (s.cur_depth.at<float>(p1i) != 0) continue;
    s.prev_depth.at<float>(p0) = static_cast<float>(depth);
    s.cur_depth.at<float>(p1i) =
        static_cast<float>((so3::Exp(-s.w_cur * RowTimeOffset(p1.y(), kHeight, kReadout)) * X_cur).z());
    const cv::Point2f prev(static_cast<float>(p0.x), static_cast<float>(p0.y));
    const cv::Point2f cur(static_cast<float>(p1.x()), static_cast<float>(p1.y()));
    s.pairs.cur.push_back(cur);
    s.pairs.cur_un.push_back(cur);  // a pinhole: raw = undistorted
    s.pairs.flow.prev.push_back(prev);
    s.pairs.prev_un.push_back(prev);
    s.pairs.flow.status.push_back(PairStatus::kOk);
    s.moving.push_back(mover);
    s.X_prev.push_back(X);
  }
  s.pairs.flow.valid = static_cast<int>(s.moving.size());
  return s;
}

RollingShutterInput Input(const Scene& s, const Eigen::Vector3d& guess) {
  RollingShutterInput in;
  in.readout = kReadout;
  in.height = kHeight;
  in.w_prev = s.w_prev;
  in.w_guess = guess;
  in.prev_depth = s.prev_depth;
  in.depth_factor = 1;
  in.K = {kFx, kFy, kCx, kCy};
  return in;
}

// Median reprojection error of the static pairs under the best rigid motion.
double RigidResidual(const std::vector<cv::Point2f>& prev_un, const std::vector<cv::Point2f>& cur_un, const Scene& s,
                     const DynamicConfig& config) {
  std::vector<bool> use(s.moving.size());
  for (std::size_t i = 0; i < use.size(); ++i) use[i] = !s.moving[i];
  const auto m = EstimateMotion(s.pairs.flow.prev, prev_un, cur_un, use, s.prev_depth, 1, {kFx, kFy, kCx, kCy}, config);
  EXPECT_TRUE(m.has_value());
  if (!m) return 1e9;
  std::vector<double> e;
  for (std::size_t i = 0; i < use.size(); ++i) {
    if (!use[i]) continue;
    const double z = s.prev_depth.at<float>(cvRound(s.pairs.flow.prev[i].y), cvRound(s.pairs.flow.prev[i].x));
    const Eigen::Vector3d X((prev_un[i].x - kCx) / kFx * z, (prev_un[i].y - kCy) / kFy * z, z);
    e.push_back((Project(m->T_cur_prev * X) - Eigen::Vector2d(cur_un[i].x, cur_un[i].y)).norm());
  }
  std::nth_element(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(e.size() / 2), e.end());
  return e[e.size() / 2];
}

TEST(RollingPairs, FitsTheCurrentVelocityAndStraightensThePairs) {
  Scene s = MakeScene(400, 60);
  DynamicConfig config;
  std::vector<bool> use(s.moving.size(), true);  // the movers are in: RANSAC must leave them out
  const double before = RigidResidual(s.pairs.prev_un, s.pairs.cur_un, s, config);
  const RollingShutterFit fit = CorrectPairsForRollingShutter(s.pairs, use, Input(s, s.w_prev), config);
  ASSERT_TRUE(fit.fitted);
  EXPECT_LT((fit.w_cur - s.w_cur).norm(), 0.05) << fit.w_cur.transpose();
  EXPECT_GT(fit.inliers, 350);
  EXPECT_EQ(fit.pairs, 460) << "every pair has a previous depth";
  EXPECT_LE(fit.inliers, fit.pairs);
  // The pairs are now where the middle-row cameras see the points.
  double worst_prev = 0, worst_cur = 0;
  for (std::size_t i = 0; i < s.moving.size(); ++i) {
    if (s.moving[i]) continue;
    const Eigen::Vector2d p0 = Project(s.X_prev[i]), p1 = Project(s.T_cur_prev * s.X_prev[i]);
    worst_prev = std::max(worst_prev, (p0 - Eigen::Vector2d(s.pairs.prev_un[i].x, s.pairs.prev_un[i].y)).norm());
    worst_cur = std::max(worst_cur, (p1 - Eigen::Vector2d(s.pairs.cur_un[i].x, s.pairs.cur_un[i].y)).norm());
  }
  EXPECT_LT(worst_prev, 0.01);
  EXPECT_LT(worst_cur, 0.1);
  const double after = RigidResidual(s.pairs.prev_un, s.pairs.cur_un, s, config);
  EXPECT_GT(before, 0.5) << "the scene must bend the images for the test to mean anything";
  EXPECT_LT(after, 0.05) << "before " << before;
  const SE3 d = fit.T_cur_prev * s.T_cur_prev.Inverse();
  EXPECT_LT(d.Log().norm(), 2e-3);
}

// Algorithm 1 with the RGB-D check (geometric mode): taken as one camera per
// image, the bent pairs cost static points; moved to their middle rows, none.
TEST(RollingPairs, JudgePairsKeepsTheStaticPointsOfABentPair) {
  const Scene s = MakeScene(400, 60);
  std::vector<cv::KeyPoint> keys;
  for (const cv::Point2f& p : s.pairs.cur) keys.emplace_back(p, 7.f);
  DynamicConfig c;
  c.mode = "geometric";
  c.eps_std = 1.0;
  const DepthCheckInput depth{s.prev_depth, s.cur_depth, 1.0, {kFx, kFy, kCx, kCy}, SE3(), {}};
  const RollingShutterInput in = Input(s, s.w_prev);
  const auto score = [&](const RejectionResult& r) {
    int static_lost = 0, movers_caught = 0;
    for (std::size_t i = 0; i < keys.size(); ++i) (s.moving[i] ? movers_caught : static_lost) += !r.keypoints[i].kept;
    return std::make_pair(static_lost, movers_caught);
  };
  c.rolling_shutter_pairs = false;
  const auto [lost_rigid, caught_rigid] = score(JudgePairs(s.pairs, keys, {}, {}, c, &depth, nullptr, &in));
  c.rolling_shutter_pairs = true;
  const RejectionResult r = JudgePairs(s.pairs, keys, {}, {}, c, &depth, nullptr, &in);
  const auto [lost, caught] = score(r);
  std::printf("static lost %d -> %d of 400, movers caught %d -> %d of 60\n", lost_rigid, lost, caught_rigid, caught);
  EXPECT_GT(lost_rigid, 15) << "the bend must cost static points for the test to mean anything";
  EXPECT_LE(lost, 2);
  EXPECT_GE(caught, 57);
  ASSERT_TRUE(r.angular_velocity.has_value());
  EXPECT_LT((*r.angular_velocity - s.w_cur).norm(), 0.05);
}

TEST(RollingPairs, AGlobalShutterLeavesThePairsAlone) {
  Scene s = MakeScene(100, 0);
  const PairSet before = s.pairs;
  RollingShutterInput in = Input(s, s.w_prev);
  in.readout = 0;
  const RollingShutterFit fit = CorrectPairsForRollingShutter(s.pairs, std::vector<bool>(100, true), in, DynamicConfig{});
  EXPECT_FALSE(fit.fitted);
  EXPECT_EQ(s.pairs.prev_un, before.prev_un);
  EXPECT_EQ(s.pairs.cur_un, before.cur_un);
}

TEST(RollingPairs, TooFewPairsKeepTheGuess) {
  Scene s = MakeScene(12, 0);
  const Eigen::Vector3d guess(0.5, -1.0, 0.2);
  const RollingShutterFit fit =
      CorrectPairsForRollingShutter(s.pairs, std::vector<bool>(12, true), Input(s, guess), DynamicConfig{});
  EXPECT_FALSE(fit.fitted);
  EXPECT_EQ(fit.w_cur, guess);
  // Both sides are still turned: the previous one with its known velocity.
  EXPECT_NE(s.pairs.prev_un[0], s.pairs.flow.prev[0]);
}

}  // namespace
}  // namespace sgslam::dynamic
