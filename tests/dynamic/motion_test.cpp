// The pieces around Algorithm 1 that work on undistorted pairs: the PnP motion of
// the RGB-D check (motion.h), JudgePairs on a distorted camera (the fr1 lens), the
// prior of the previous frame's rejections, and TrackPairs' undistortion step.
#include <gtest/gtest.h>

#include <random>

#include "dynamic/dynamic_test_scene.h"
#include "sgslam/camera/camera.h"
#include "sgslam/dynamic/motion.h"

namespace sgslam::dynamic {
namespace {

constexpr double kFx = 517.3, kFy = 516.5, kCx = 318.6, kCy = 255.3;

CameraConfig Fr1() {
  CameraConfig c;
  c.width = 640, c.height = 480;
  c.fx = kFx, c.fy = kFy, c.cx = kCx, c.cy = kCy;
  c.k1 = 0.2624, c.k2 = -0.9531, c.p1 = -0.0054, c.p2 = 0.0026, c.k3 = 1.1633;
  return c;
}

// Static points 1-5 m in front of the previous camera spread over the whole image,
// seen after a hand-held-like motion (mostly rotation), plus `movers` points that
// also moved 3 cm sideways between the frames. Positions are given undistorted
// and, through the fr1 lens, raw; depth is stored at the raw previous pixels.
struct Scene {
  SE3 T_cur_prev;
  std::vector<cv::Point2f> prev_un, cur_un, prev_raw, cur_raw;
  std::vector<bool> moving;
  cv::Mat prev_depth, cur_depth;  // CV_32F, m
  Pinhole K{kFx, kFy, kCx, kCy};
};

Scene MakeScene(int n_static, int movers, unsigned seed = 3) {
  const Camera camera(Fr1());
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1), z(1, 5);
  Scene s;
  Vector6d xi;
  xi << 0.004, -0.003, 0.002, 0.02, -0.015, 0.01;  // ~1.5 deg of rotation, ~5 mm of translation
  s.T_cur_prev = SE3::Exp(xi);
  s.prev_depth = cv::Mat(480, 640, CV_32F, cv::Scalar(0));
  s.cur_depth = cv::Mat(480, 640, CV_32F, cv::Scalar(0));
  auto project = [&](const Eigen::Vector3d& X) { return Eigen::Vector2d(kFx * X.x() / X.z() + kCx, kFy * X.y() / X.z() + kCy); };
  auto inside = [](const Eigen::Vector2d& p) { return p.x() > 12 && p.y() > 12 && p.x() < 628 && p.y() < 468; };
  while (static_cast<int>(s.moving.size()) < n_static + movers) {
    const bool mover = static_cast<int>(s.moving.size()) >= n_static;
    // A raw previous pixel (integer: the depth lookup rounds, and the lifted point
    // is then exact), its undistorted position and ray.
    const cv::Point p0(20 + static_cast<int>(600 * u(rng)), 20 + static_cast<int>(440 * u(rng)));
    std::vector<cv::Point2f> un = {cv::Point2f(static_cast<float>(p0.x), static_cast<float>(p0.y))};
    camera.Undistort(un);
    const double depth = z(rng);
    const Eigen::Vector3d X((un[0].x - kCx) / kFx * depth, (un[0].y - kCy) / kFy * depth, depth);
    const Eigen::Vector3d Xc = s.T_cur_prev * (X + (mover ? Eigen::Vector3d(0.03, 0, 0) : Eigen::Vector3d::Zero()));
    const Eigen::Vector2d u1 = project(Xc);
    const Eigen::Vector2d r1 = camera.Distort(u1);
    if (!inside(r1)) continue;
    const cv::Point p1(cvRound(r1.x()), cvRound(r1.y()));
    if (s.prev_depth.at<float>(p0) != 0 || s.cur_depth.at<float>(p1) != 0) continue;  // one point per pixel
    s.prev_depth.at<float>(p0) = static_cast<float>(X.z());
    s.cur_depth.at<float>(p1) = static_cast<float>(Xc.z());
    s.prev_raw.emplace_back(static_cast<float>(p0.x), static_cast<float>(p0.y));
    s.cur_raw.emplace_back(static_cast<float>(r1.x()), static_cast<float>(r1.y()));
    s.prev_un.push_back(un[0]);
    s.cur_un.emplace_back(static_cast<float>(u1.x()), static_cast<float>(u1.y()));
    s.moving.push_back(mover);
  }
  return s;
}

double RotationErrorDeg(const SE3& a, const SE3& b) {
  const Eigen::AngleAxisd d(a.rotation().transpose() * b.rotation());
  return d.angle() * 180.0 / M_PI;
}

TEST(Motion, PnpRecoversTheCameraMotionDespiteMovers) {
  const Scene s = MakeScene(300, 100);
  const std::vector<bool> all(s.moving.size(), true);
  const auto est = EstimateMotion(s.prev_raw, s.prev_un, s.cur_un, all, s.prev_depth, 1.0, s.K);
  ASSERT_TRUE(est);
  EXPECT_EQ(est->pairs, 400);
  EXPECT_GE(est->inliers, 295);  // the 300 static points (float rounding aside)
  EXPECT_LE(est->inliers, 330);  // few movers happen to fit
  EXPECT_LT(RotationErrorDeg(est->T_cur_prev, s.T_cur_prev), 0.01);
  EXPECT_LT((est->T_cur_prev.translation() - s.T_cur_prev.translation()).norm(), 1e-3);  // m
  // Deterministic for equal inputs.
  const auto again = EstimateMotion(s.prev_raw, s.prev_un, s.cur_un, all, s.prev_depth, 1.0, s.K);
  ASSERT_TRUE(again);
  EXPECT_EQ(again->T_cur_prev.translation(), est->T_cur_prev.translation());
}

TEST(Motion, NoEstimateWithoutEnoughDepth) {
  const Scene s = MakeScene(40, 0);
  static_assert(kMotionMinInliers > 20, "the 20 pairs below must be too few");
  std::vector<bool> few(s.moving.size(), false);
  for (int i = 0; i < 20; ++i) few[i] = true;
  EXPECT_FALSE(EstimateMotion(s.prev_raw, s.prev_un, s.cur_un, few, s.prev_depth, 1.0, s.K));
  // All 40 (enough pairs) but no depth.
  EXPECT_FALSE(EstimateMotion(s.prev_raw, s.prev_un, s.cur_un, std::vector<bool>(40, true), cv::Mat(), 1.0, s.K));
}

// A PairSet as TrackPairs would make it, from known positions.
PairSet Pairs(const Scene& s, bool undistorted) {
  PairSet p;
  p.cur = s.cur_raw;
  p.flow.prev = s.prev_raw;
  p.flow.status.assign(s.cur_raw.size(), PairStatus::kOk);
  p.flow.valid = static_cast<int>(s.cur_raw.size());
  p.prev_un = undistorted ? s.prev_un : s.prev_raw;
  p.cur_un = undistorted ? s.cur_un : s.cur_raw;
  return p;
}

std::vector<cv::KeyPoint> Keys(const Scene& s) {
  std::vector<cv::KeyPoint> k;
  for (const auto& p : s.cur_raw) k.emplace_back(p, 7.f);
  return k;
}

struct Tally {
  int static_rejected = 0, moving_rejected = 0, movers = 0, statics = 0;
};
Tally Count(const Scene& s, const RejectionResult& r) {
  Tally t;
  for (size_t i = 0; i < s.moving.size(); ++i) {
    (s.moving[i] ? t.movers : t.statics) += 1;
    if (!r.keypoints[i].kept) (s.moving[i] ? t.moving_rejected : t.static_rejected) += 1;
  }
  return t;
}

TEST(Motion, EpipolarTestNeedsUndistortedPairsOnTheFr1Lens) {
  const Scene s = MakeScene(400, 0);
  DynamicConfig c;
  c.mode = "geometric";
  c.eps_std = 1.0;
  c.refinements.depth_check = false;
  const auto keys = Keys(s);
  const RejectionResult un = JudgePairs(ParseMode(c.mode), Pairs(s, true), keys, {}, {}, c);
  const RejectionResult raw = JudgePairs(ParseMode(c.mode), Pairs(s, false), keys, {}, {}, c);
  ASSERT_TRUE(un.fundamental && raw.fundamental);
  double worst_un = 0;
  int raw_over = 0;
  for (size_t i = 0; i < keys.size(); ++i) {
    worst_un = std::max(worst_un, un.keypoints[i].distance);
    raw_over += raw.keypoints[i].distance > 0.5;
  }
  std::printf("static pairs: max d undistorted %.4f px; raw pairs with d > 0.5 px: %d of %zu\n", worst_un, raw_over,
              keys.size());
  EXPECT_LT(worst_un, 0.05);  // exact geometry up to float rounding
  EXPECT_EQ(Count(s, un).static_rejected, 0);
  EXPECT_GT(raw_over, 20);  // the lens bends the epipolar lines at the periphery
}

TEST(Motion, DepthCheckWithPnpMotionCatchesMoversOnTheFr1Lens) {
  const Scene s = MakeScene(300, 100);
  DynamicConfig c;
  c.mode = "geometric";
  c.eps_std = 1e3;  // the epipolar test off: the RGB-D check alone
  c.refinements.depth_check = true;
  DepthCheckInput depth{s.prev_depth, s.cur_depth, 1.0, s.K, SE3(), {}};  // the motion comes from PnP
  const RejectionResult r = JudgePairs(ParseMode(c.mode), Pairs(s, true), Keys(s), {}, {}, c, &depth);
  ASSERT_TRUE(r.motion);
  const Tally t = Count(s, r);
  std::printf("pnp depth check: %d of %d movers, %d of %d static rejected\n", t.moving_rejected, t.movers,
              t.static_rejected, t.statics);
  EXPECT_GE(t.moving_rejected, 90);  // 3 cm at 1-5 m: 3-15 px, above the 3 px tolerance
  EXPECT_EQ(t.static_rejected, 0);
  EXPECT_FALSE(r.depth_ignored);
  // A previous depth 1.5 times too far (a wrong depth scale) makes every point's
  // predicted depth wrong: a check that flags most of the frame is ignored for it...
  DepthCheckInput scaled = depth;
  scaled.prev_depth = s.prev_depth * 1.5;
  const RejectionResult bad = JudgePairs(ParseMode(c.mode), Pairs(s, true), Keys(s), {}, {}, c, &scaled);
  EXPECT_TRUE(bad.depth_ignored);
  EXPECT_EQ(Count(s, bad).static_rejected, 0);
  EXPECT_EQ(bad.rejected_depth, 0);
  // ... unless the share limit (kDepthMaxShare) is lifted.
  Algorithm1Params lifted;
  lifted.depth.max_share = 1.0;
  const RejectionResult trusted =
      JudgePairs(ParseMode(c.mode), Pairs(s, true), Keys(s), {}, {}, c, &scaled, nullptr, lifted);
  EXPECT_FALSE(trusted.depth_ignored);
  EXPECT_GT(Count(s, trusted).static_rejected, 200);
}

TEST(Motion, PriorCellsAreLeftOutOfTheFits) {
  const Scene s = MakeScene(300, 100);
  const auto keys = Keys(s);
  // A previous frame whose verdicts rejected every point left of x = 320.
  RejectionResult previous;
  previous.keypoints.resize(keys.size());
  std::vector<cv::KeyPoint> prev_keys;
  int left = 0;
  for (size_t i = 0; i < keys.size(); ++i) {
    prev_keys.emplace_back(s.prev_raw[i], 7.f);
    previous.keypoints[i].kept = s.prev_raw[i].x >= 320;
    left += s.prev_raw[i].x < 320;
  }
  const DynamicPrior prior = MakeDynamicPrior(prev_keys, previous, {640, 480}, 20);
  EXPECT_EQ(prior.cell, 20);
  EXPECT_TRUE(prior.Dynamic(s.prev_raw[0]) == (s.prev_raw[0].x < 320));
  EXPECT_FALSE(prior.Dynamic({700, 10}));  // outside: no prior
  EXPECT_FALSE(DynamicPrior{}.Dynamic({10, 10}));
  DynamicConfig c;
  c.mode = "geometric";
  c.refinements.depth_check = false;
  const RejectionResult without = JudgePairs(ParseMode(c.mode), Pairs(s, true), keys, {}, {}, c);
  const RejectionResult with = JudgePairs(ParseMode(c.mode), Pairs(s, true), keys, {}, {}, c, nullptr, &prior);
  ASSERT_TRUE(without.fundamental && with.fundamental);
  EXPECT_EQ(without.fundamental->pairs, 400);
  EXPECT_EQ(with.fundamental->pairs, 400 - left);
}

// R3's memory (kPriorMemory): a cell whose keypoints were rejected stays out of the fits
// while their flow-tracked successors are kept, for memory - 1 more frames.
TEST(Motion, PriorRemembersRejectionsForSomeFrames) {
  const cv::Size image(640, 480);
  const std::vector<cv::KeyPoint> keys = {cv::KeyPoint(30, 30, 7), cv::KeyPoint(35, 32, 7), cv::KeyPoint(300, 300, 7)};
  RejectionResult rejected;  // frame 0: the two keypoints of cell (1, 1) rejected
  rejected.keypoints.resize(3);
  rejected.keypoints[0].kept = rejected.keypoints[1].kept = false;
  // The next frames keep everything; their flow leads back into the same cell.
  RejectionResult kept;
  kept.keypoints.resize(3);
  for (size_t i = 0; i < 3; ++i) kept.keypoints[i].pair = PairStatus::kOk, kept.keypoints[i].prev = keys[i].pt;
  for (int memory : {1, 3}) {
    DynamicPrior prior = MakeDynamicPrior(keys, rejected, image, 20, nullptr, memory);
    EXPECT_EQ(prior.Memory({30, 30}), memory);
    EXPECT_FALSE(prior.Dynamic({300, 300}));
    for (int frame = 1; frame <= 3; ++frame) {
      prior = MakeDynamicPrior(keys, kept, image, 20, &prior, memory);
      EXPECT_EQ(prior.Dynamic({30, 30}), frame < memory) << "memory " << memory << ", frame " << frame;
    }
  }
  // A successor without a flow pair has no past to inherit.
  RejectionResult unpaired = kept;
  for (auto& v : unpaired.keypoints) v.pair = PairStatus::kFlowFailed;
  const DynamicPrior first = MakeDynamicPrior(keys, rejected, image, 20, nullptr, 3);
  EXPECT_FALSE(MakeDynamicPrior(keys, unpaired, image, 20, &first, 3).Dynamic({30, 30}));
}

// R5's confirmation (kConfirmStatic): static points in a dynamic box that the RGB-D check
// passes well within its tolerances are judged without the box weight; movers in
// the box are not confirmed.
TEST(Motion, StaticPointsTheRgbdCheckConfirmsAreJudgedWithoutTheBoxWeight) {
  const Scene s = MakeScene(300, 100);
  DynamicConfig c;
  c.mode = "sg";
  c.refinements.depth_check = true;
  c.refinements.box_depth_band = false;  // every keypoint in the box is weighted
  const DepthCheckInput depth{s.prev_depth, s.cur_depth, 1.0, s.K, SE3(), {}};
  const std::vector<Detection> box = {Detection{0, "person", 0.9f, cv::Rect2f(0, 0, 320, 480)}};
  const WeightFn huge = [](const std::string&) { return 1e9; };  // any d > 0 fails d * w < eps
  const auto in_box = [&](const RejectionResult& r, bool moving) {
    int n = 0, rejected = 0;
    for (size_t i = 0; i < s.moving.size(); ++i) {
      if (s.moving[i] != moving || s.cur_raw[i].x >= 320) continue;
      ++n, rejected += !r.keypoints[i].kept;
    }
    return std::pair{n, rejected};
  };
  Algorithm1Params off;
  off.depth.confirm_static = 0;
  const RejectionResult plain =
      JudgePairs(ParseMode(c.mode), Pairs(s, true), Keys(s), box, huge, c, &depth, nullptr, off);
  const RejectionResult confirmed =
      JudgePairs(ParseMode(c.mode), Pairs(s, true), Keys(s), box, huge, c, &depth);  // kConfirmStatic
  const auto [statics, plain_lost] = in_box(plain, false);
  const auto [statics2, confirmed_lost] = in_box(confirmed, false);
  const auto [movers, movers_caught] = in_box(confirmed, true);
  std::printf("static in the box: %d, lost %d without, %d with confirmation; movers %d, %d rejected\n", statics,
              plain_lost, confirmed_lost, movers, movers_caught);
  ASSERT_GT(statics, 100);
  ASSERT_GT(movers, 30);
  EXPECT_GE(plain_lost, statics * 9 / 10);
  EXPECT_LE(confirmed_lost, statics / 10);  // measured 11 of 150: PnP on the right half is not exact
  EXPECT_EQ(movers_caught, movers);
}

// dynamic.refinements.appearance_pairs (R4): pairs that failed only the appearance filter are
// not used for F, but one beyond eps_std is rejected; within it, kept untested.
TEST(Motion, AppearanceFailedPairsBeyondEpsAreRejected) {
  const Scene s = MakeScene(300, 0);
  PairSet pairs = Pairs(s, true);
  std::vector<size_t> failed;
  for (size_t i = 0; i < s.moving.size(); i += 3) {
    pairs.flow.status[i] = PairStatus::kAppearance;
    --pairs.flow.valid;
    failed.push_back(i);
  }
  DynamicConfig c;
  c.mode = "sg";
  c.refinements.depth_check = false;
  const RejectionResult before = JudgePairs(ParseMode(c.mode), pairs, Keys(s), {}, {}, c);
  ASSERT_TRUE(before.fundamental);
  EXPECT_EQ(before.fundamental->pairs, pairs.flow.valid);  // not used for F
  // Half of them "moved": 10 px across their epipolar line.
  const Eigen::Matrix3d& F = before.fundamental->F_cur_prev;
  for (size_t k = 0; k < failed.size(); k += 2) {
    const size_t i = failed[k];
    EXPECT_TRUE(before.keypoints[i].kept);
    const Eigen::Vector3d l = F * Eigen::Vector3d(pairs.prev_un[i].x, pairs.prev_un[i].y, 1.0);
    const Eigen::Vector2d n = l.head<2>().normalized() * 10.0;
    pairs.cur_un[i] += cv::Point2f(static_cast<float>(n.x()), static_cast<float>(n.y()));
  }
  const auto count = [&](const RejectionResult& r, size_t parity) {
    int rejected = 0;
    for (size_t k = parity; k < failed.size(); k += 2) rejected += !r.keypoints[failed[k]].kept;
    return rejected;
  };
  c.refinements.appearance_pairs = false;
  const RejectionResult off = JudgePairs(ParseMode(c.mode), pairs, Keys(s), {}, {}, c);
  EXPECT_EQ(count(off, 0) + count(off, 1), 0);  // untested, kept
  c.refinements.appearance_pairs = true;
  const RejectionResult on = JudgePairs(ParseMode(c.mode), pairs, Keys(s), {}, {}, c);
  const int moved = static_cast<int>((failed.size() + 1) / 2);
  EXPECT_EQ(count(on, 0), moved);
  EXPECT_EQ(count(on, 1), 0);
  EXPECT_EQ(on.keypoints[failed[0]].why, Why::kGeometry);
  EXPECT_EQ(on.keypoints[failed[1]].why, Why::kUnjudged);
}

TEST(Motion, TrackPairsUndistortsBothPositions) {
  const test::FramePair p = test::MakePair("static", 10);
  const auto keys = test::DetectKeypoints(p.cur_gray, 200);
  DynamicConfig c;
  const UndistortPointsFn shift = [](std::vector<cv::Point2f>& v) {
    for (auto& x : v) x += cv::Point2f(1.f, -2.f);
  };
  const PairSet a = TrackPairs(FlowFrame{p.prev_gray, {}}, FlowFrame{p.cur_gray, {}}, keys, c, shift);
  ASSERT_EQ(a.cur.size(), keys.size());
  for (size_t i = 0; i < keys.size(); ++i) {
    EXPECT_EQ(a.cur[i], keys[i].pt);
    EXPECT_EQ(a.cur_un[i], keys[i].pt + cv::Point2f(1.f, -2.f));
    EXPECT_EQ(a.prev_un[i], a.flow.prev[i] + cv::Point2f(1.f, -2.f));
  }
  c.refinements.undistort_pairs = false;
  const PairSet b = TrackPairs(FlowFrame{p.prev_gray, {}}, FlowFrame{p.cur_gray, {}}, keys, c, shift);
  for (size_t i = 0; i < keys.size(); ++i) EXPECT_EQ(b.cur_un[i], keys[i].pt);
}

}  // namespace
}  // namespace sgslam::dynamic
