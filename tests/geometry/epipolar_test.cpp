// The fundamental matrix and eq. (4): against the analytic F of a known pose, its
// direction (previous -> lines in the current image), robustness and determinism.
#include <gtest/gtest.h>

#include <random>

#include "sgslam/geometry/epipolar.h"

namespace sgslam::geometry {
namespace {

struct TwoViews {
  std::vector<Eigen::Vector2d> prev, cur;
  SE3 T_cur_prev;
  Eigen::Matrix3d K;
};

// Random points 1-6 m in front of the previous camera seen after a general motion.
TwoViews Project(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), z(1, 6);
  TwoViews v;
  v.K << 525, 0, 319.5, 0, 525, 239.5, 0, 0, 1;
  Vector6d xi;
  xi << 0.05, -0.02, 0.03, 0.01, -0.02, 0.015;
  v.T_cur_prev = SE3::Exp(xi);
  while (static_cast<int>(v.prev.size()) < n) {
    const double depth = z(rng);
    const Eigen::Vector3d X(u(rng) * 0.6 * depth, u(rng) * 0.45 * depth, depth);
    const Eigen::Vector3d Xc = v.T_cur_prev * X;
    if (Xc.z() < 0.5) continue;
    v.prev.push_back((v.K * X).hnormalized());
    v.cur.push_back((v.K * Xc).hnormalized());
  }
  return v;
}

Pinhole PinholeOf(const Eigen::Matrix3d& K) { return {K(0, 0), K(1, 1), K(0, 2), K(1, 2)}; }

double MaxDistance(const Eigen::Matrix3d& F, const TwoViews& v) {
  double worst = 0;
  for (size_t i = 0; i < v.prev.size(); ++i) worst = std::max(worst, EpipolarDistance(F, v.prev[i], v.cur[i]));
  return worst;
}

TEST(Epipolar, AnalyticFundamentalHoldsForProjectedPoints) {
  const TwoViews v = Project(200, 1);
  EXPECT_LT(MaxDistance(FundamentalMatrix(v.T_cur_prev, PinholeOf(v.K)), v), 1e-9);
  // Direction: the transpose maps current points to previous lines, not the reverse.
  EXPECT_GT(MaxDistance(FundamentalMatrix(v.T_cur_prev, PinholeOf(v.K)).transpose(), v), 1.0);
}

TEST(Epipolar, EstimateMatchesTheAnalyticFundamental) {
  const TwoViews v = Project(300, 2);
  const std::vector<bool> all(v.prev.size(), true);
  const FundamentalOptions c;
  // OpenCV's 7-point model works on float-rounded points.
  const auto raw = EstimateFundamental(v.prev, v.cur, all, c);
  ASSERT_TRUE(raw);
  EXPECT_LT(MaxDistance(raw->F_cur_prev, v), 1e-2);
  EXPECT_EQ(raw->inliers, 300);
}

TEST(Epipolar, RansacIgnoresMovingPointsAndIsDeterministic) {
  TwoViews v = Project(400, 3);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 0.2);
  for (size_t i = 0; i < v.cur.size(); ++i) {
    v.cur[i] += Eigen::Vector2d(noise(rng), noise(rng));
    if (i % 4 == 0) v.cur[i] += Eigen::Vector2d(6, -4);  // a quarter moved by (6, -4) px
  }
  const std::vector<bool> all(v.prev.size(), true);
  const FundamentalOptions c;
  const auto a = EstimateFundamental(v.prev, v.cur, all, c), b = EstimateFundamental(v.prev, v.cur, all, c);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->F_cur_prev, b->F_cur_prev);  // bit-identical: OpenCV seeds its RNG per call
  // A moved point is visible only through the part of its motion across its true
  // epipolar line; those clearly across it (> 2 px) must be caught.
  const Eigen::Matrix3d F_true = FundamentalMatrix(v.T_cur_prev, PinholeOf(v.K));
  int across = 0, caught = 0, static_ok = 0;
  for (size_t i = 0; i < v.prev.size(); ++i) {
    const double d = EpipolarDistance(a->F_cur_prev, v.prev[i], v.cur[i]);
    if (i % 4 != 0) {
      static_ok += d < 1.0;
    } else if (EpipolarDistance(F_true, v.prev[i], v.cur[i]) > 2.0) {
      ++across;
      caught += d > 1.0;
    }
  }
  EXPECT_GT(across, 25);
  EXPECT_GE(caught, 0.95 * across);
  EXPECT_GE(static_ok, 0.95 * 300);
}

TEST(Epipolar, FitsOnPreferredPairsWhenEnoughRemain) {
  const TwoViews v = Project(100, 4);
  std::vector<bool> preferred(v.prev.size(), false);
  FundamentalOptions c;
  for (int i = 0; i < c.min_preferred - 1; ++i) preferred[i] = true;
  auto est = EstimateFundamental(v.prev, v.cur, preferred, c);
  ASSERT_TRUE(est);
  EXPECT_FALSE(est->from_static);
  EXPECT_EQ(est->pairs, 100);
  preferred[c.min_preferred - 1] = true;
  est = EstimateFundamental(v.prev, v.cur, preferred, c);
  ASSERT_TRUE(est);
  EXPECT_TRUE(est->from_static);
  EXPECT_EQ(est->pairs, c.min_preferred);
  EXPECT_FALSE(EstimateFundamental({v.prev.begin(), v.prev.begin() + 7}, {v.cur.begin(), v.cur.begin() + 7},
                                   std::vector<bool>(7, true), c));
}

}  // namespace
}  // namespace sgslam::geometry
