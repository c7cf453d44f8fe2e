// RPE against cases with a known answer, including evaluate_rpe.py's quirks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <random>

#include "sgslam/common/error.h"
#include "sgslam/eval/rpe.h"

namespace sgslam::eval {
namespace {

constexpr Timestamp kT0 = 1'305'031'225'000'000'000;
constexpr Timestamp kMs = 1'000'000;

SE3 RotZ(double angle) { return SE3(so3::Exp(Eigen::Vector3d(0, 0, angle)), Eigen::Vector3d::Zero()); }

// Turning orientation; positions on the z axis when on_z_axis (see the rotation test).
Trajectory Path(int n, Timestamp dt, bool on_z_axis = false) {
  Trajectory out;
  for (int i = 0; i < n; ++i) {
    const double s = i * ToSeconds(dt);
    Eigen::Vector3d p(1.5 * std::sin(0.5 * s), 0.8 * std::cos(0.3 * s), 0.4 * std::sin(0.9 * s + 1.0));
    if (on_z_axis) p.head<2>().setZero();
    const Eigen::Vector3d phi(0.3 * std::sin(0.4 * s), 0.2 * std::cos(0.25 * s), 0.5 * s);
    out.push_back({kT0 + i * dt, SE3(so3::Exp(phi), p)});
  }
  return out;
}

std::vector<Timestamp> Seconds(std::initializer_list<int> s) {
  std::vector<Timestamp> out;
  for (int v : s) out.push_back(v * kNsPerSecond);
  return out;
}

TEST(EvalRpe, FindClosestIndexBreaksTiesLikeTheScript) {
  const std::vector<Timestamp> L = Seconds({0, 1, 2, 3});
  const Timestamp half = kNsPerSecond / 2;
  EXPECT_EQ(FindClosestIndex(L, half), 0u);                     // tie 0|1: keeps index 0
  EXPECT_EQ(FindClosestIndex(L, kNsPerSecond + half), 2u);      // tie 1|2: first visited is 2
  EXPECT_EQ(FindClosestIndex(L, 2 * kNsPerSecond + half), 2u);  // tie 2|3: first visited is 2
  EXPECT_EQ(FindClosestIndex(L, 3 * kNsPerSecond), 3u);
  EXPECT_EQ(FindClosestIndex(L, -5 * kNsPerSecond), 0u);
  EXPECT_EQ(FindClosestIndex(L, 9 * kNsPerSecond), 3u);
}

TEST(EvalRpe, FindClosestIndexFindsANearestStamp) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<Timestamp> stamp(0, 1000);
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<Timestamp> L(1 + trial % 17);
    for (Timestamp& t : L) t = stamp(rng);
    std::sort(L.begin(), L.end());
    L.erase(std::unique(L.begin(), L.end()), L.end());
    const Timestamp t = stamp(rng) - 20;
    Timestamp best = std::numeric_limits<Timestamp>::max();
    for (Timestamp v : L) best = std::min(best, std::abs(v - t));
    EXPECT_EQ(std::abs(L[FindClosestIndex(L, t)] - t), best);
  }
}

TEST(EvalRpe, IdenticalTrajectoryHasZeroError) {
  const Trajectory gt = Path(1000, 10 * kMs);
  const RpeResult rpe = ComputeRpe(gt, gt, kNsPerSecond);
  EXPECT_GT(rpe.pairs.size(), 800u);
  EXPECT_LT(rpe.trans.max, 1e-12);
  EXPECT_LT(rpe.rot_deg.max, 1e-5);  // arccos of the trace resolves ~1e-6 deg near 0
}

TEST(EvalRpe, PairsEndingOnTheLastPoseAreDropped) {
  // Estimate at 0..4 s, delta 1 s: (3, 4) is a perfect pair, but the script
  // drops every pair whose end is the last pose, so only 3 pairs remain.
  const Trajectory gt = Path(41, 100 * kMs);
  Trajectory est;
  for (int k = 0; k <= 4; ++k) est.push_back(gt[10 * k]);
  const RpeResult rpe = ComputeRpe(gt, est, kNsPerSecond);
  ASSERT_EQ(rpe.pairs.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(rpe.pairs[k].est0, k);
    EXPECT_EQ(rpe.pairs[k].est1, k + 1);
    EXPECT_EQ(rpe.pairs[k].gt0, 10 * k);
    EXPECT_EQ(rpe.pairs[k].gt1, 10 * (k + 1));
  }
}

TEST(EvalRpe, ConstantExtraRotationPerSecond) {
  // est = Rz(a t) * gt with gt on the z axis: every error is a pure rotation by a*delta.
  const double a = 2.0 * std::numbers::pi / 180.0;  // 2 deg/s
  const Trajectory gt = Path(1000, 10 * kMs, true);
  Trajectory est = gt;
  for (StampedPose& p : est) p.T_w_c = RotZ(a * ToSeconds(p.t - kT0)) * p.T_w_c;
  const RpeResult rpe = ComputeRpe(gt, est, kNsPerSecond);
  EXPECT_NEAR(rpe.rot_deg.min, 2.0, 1e-6);
  EXPECT_NEAR(rpe.rot_deg.max, 2.0, 1e-6);
  EXPECT_NEAR(rpe.rot_deg.rmse, 2.0, 1e-6);
  EXPECT_LT(rpe.trans.max, 1e-9);
}

TEST(EvalRpe, KnownRelativeTranslationError) {
  // est = (I, v t) * gt: the error of a pair delta apart is |v| * delta, rotation 0.
  const Eigen::Vector3d v(0.03, -0.04, 0.0);  // 5 cm/s
  const Trajectory gt = Path(1000, 10 * kMs);
  Trajectory est = gt;
  for (StampedPose& p : est) {
    p.T_w_c = SE3(Eigen::Quaterniond::Identity(), v * ToSeconds(p.t - kT0)) * p.T_w_c;
  }
  const RpeResult rpe = ComputeRpe(gt, est, 2 * kNsPerSecond);
  EXPECT_NEAR(rpe.trans.min, 0.1, 1e-9);
  EXPECT_NEAR(rpe.trans.max, 0.1, 1e-9);
  EXPECT_NEAR(rpe.trans.median, 0.1, 1e-9);
  EXPECT_LT(rpe.rot_deg.max, 1e-5);
}

TEST(EvalRpe, SkipsPairsFarFromAnyGroundTruthStamp) {
  // gt at 10 Hz over 0..10 s without 4.1..5.9 s; est at 10 Hz. An est stamp is usable
  // when a gt stamp is within 2 * 0.1 s: indices 0..42 and 58..100. Pairs (i, i+10)
  // with i+10 != 100 and both ends usable: i in 0..32 and 58..89, so 33 + 32.
  const Trajectory full = Path(101, 100 * kMs);
  Trajectory gt;
  for (int i = 0; i <= 100; ++i) {
    if (i <= 40 || i >= 60) gt.push_back(full[i]);
  }
  const RpeResult rpe = ComputeRpe(gt, full, kNsPerSecond);
  ASSERT_EQ(rpe.pairs.size(), 65u);
  EXPECT_EQ(rpe.pairs[32].est1, 42u);
  EXPECT_EQ(gt[rpe.pairs[32].gt1].t, full[40].t);  // 4.2 s compared with gt at 4.0 s
  EXPECT_EQ(rpe.pairs[33].est0, 58u);
}

TEST(EvalRpe, ThinsToTenThousandPairsDeterministically) {
  const Trajectory gt = Path(12000, 10 * kMs);
  const RpeResult a = ComputeRpe(gt, gt, kNsPerSecond);
  EXPECT_TRUE(a.thinned);
  ASSERT_EQ(a.pairs.size(), kRpeMaxPairs);
  EXPECT_EQ(a.pairs.front().est0, 0u);
  const RpeResult b = ComputeRpe(gt, gt, kNsPerSecond);
  EXPECT_EQ(a.pairs.back().est0, b.pairs.back().est0);
  EXPECT_FALSE(ComputeRpe(gt, Trajectory(gt.begin(), gt.begin() + 5000), kNsPerSecond).thinned);
}

TEST(EvalRpe, TooShortOrDisjointEstimatesAreInputErrors) {
  const Trajectory gt = Path(300, 10 * kMs);
  // Two poses 0.5 s apart: the only candidate ends on the last pose.
  EXPECT_THROW(ComputeRpe(gt, {gt[0], gt[50]}, kNsPerSecond), InputError);
  Trajectory later = gt;
  for (StampedPose& p : later) p.t += 100 * kNsPerSecond;
  EXPECT_THROW(ComputeRpe(gt, later, kNsPerSecond), InputError);
}

}  // namespace
}  // namespace sgslam::eval
