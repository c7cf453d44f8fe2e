// ATE and its statistics against cases with a known answer.
#include <gtest/gtest.h>

#include "sgslam/common/stats.h"

#include <cmath>
#include <random>

#include "sgslam/common/error.h"
#include "sgslam/eval/ate.h"
#include "sgslam/eval/stats.h"

namespace sgslam::eval {
namespace {

constexpr Timestamp kT0 = 1'305'031'225'000'000'000;
constexpr Timestamp kMs = 1'000'000;

// A smooth, non-planar 100 Hz path with turning orientation.
Trajectory SmoothPath(int n, Timestamp dt = 10 * kMs) {
  Trajectory out;
  for (int i = 0; i < n; ++i) {
    const double s = i * ToSeconds(dt);
    const Eigen::Vector3d p(1.5 * std::sin(0.5 * s), 0.8 * std::cos(0.3 * s), 0.4 * std::sin(0.9 * s + 1.0));
    const Eigen::Vector3d phi(0.3 * std::sin(0.4 * s), 0.2 * std::cos(0.25 * s), 0.05 * s);
    out.push_back({kT0 + i * dt, SE3(so3::Exp(phi), p)});
  }
  return out;
}

Trajectory Offset(const Trajectory& gt, const std::function<Eigen::Vector3d(std::size_t)>& offset) {
  Trajectory est = gt;
  for (std::size_t i = 0; i < est.size(); ++i) {
    est[i].T_w_c = SE3(est[i].T_w_c.quaternion(), est[i].T_w_c.translation() + offset(i));
  }
  return est;
}

TEST(EvalStats, MedianFollowsNumpyForOddAndEvenCounts) {
  EXPECT_DOUBLE_EQ(Median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_DOUBLE_EQ(Median({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_DOUBLE_EQ(Median({5.0}), 5.0);
  EXPECT_DOUBLE_EQ(Median({7.0, -1.0}), 3.0);
  EXPECT_DOUBLE_EQ(Median({}), 0.0);
}

TEST(EvalStats, StdIsThePopulationStd) {
  const ErrorStats s = ComputeStats({1.0, 2.0, 3.0, 4.0});
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(7.5));
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));  // ddof = 0; the sample std would be 1.29
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 4.0);
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(ComputeStats({0.3, 0.3, 0.3}).std, 0.0);
}

TEST(EvalAte, RigidlyMovedCopyHasZeroErrorAndTheInverseAlignment) {
  const Trajectory gt = SmoothPath(500);
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    const SE3 M(so3::Exp(Eigen::Vector3d(normal(rng), normal(rng), normal(rng))),
                Eigen::Vector3d(normal(rng), normal(rng), normal(rng)) * 5.0);
    Trajectory est = gt;
    for (StampedPose& p : est) p.T_w_c = M * p.T_w_c;
    const AteResult ate = ComputeAte(gt, est, 20 * kMs);
    EXPECT_EQ(ate.stats.count, gt.size());
    EXPECT_LT(ate.stats.rmse, 1e-9);
    EXPECT_LT(ate.stats.max, 1e-9);
    EXPECT_LT((ate.T_gt_est.matrix() - M.Inverse().matrix()).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(EvalAte, AlternatingOffsetGivesExactlyTheOffset) {
  const double d = 0.01;
  const Eigen::Vector3d u = Eigen::Vector3d(1.0, -2.0, 0.5).normalized();
  // Pairs of poses sharing a position make sum(s_i * p_i) vanish, so the best
  // rotation is exactly the identity and every error is exactly d.
  Trajectory paired = SmoothPath(400);
  for (std::size_t i = 1; i < paired.size(); i += 2) {
    paired[i].T_w_c = SE3(paired[i].T_w_c.quaternion(), paired[i - 1].T_w_c.translation());
  }
  const auto alternating = [&](std::size_t i) -> Eigen::Vector3d { return (i % 2 == 0 ? d : -d) * u; };
  const AteResult exact = ComputeAte(paired, Offset(paired, alternating), 20 * kMs);
  EXPECT_NEAR(exact.stats.rmse, d, 1e-12);
  EXPECT_NEAR(exact.stats.mean, d, 1e-12);
  EXPECT_NEAR(exact.stats.median, d, 1e-12);
  EXPECT_NEAR(exact.stats.std, 0.0, 1e-12);
  // On a smooth path consecutive positions nearly cancel: still d within 1e-5.
  const Trajectory gt = SmoothPath(400);
  const AteResult smooth = ComputeAte(gt, Offset(gt, alternating), 20 * kMs);
  EXPECT_NEAR(smooth.stats.rmse, d, 1e-5);
  EXPECT_NEAR(smooth.stats.mean, d, 1e-5);
  EXPECT_NEAR(smooth.stats.median, d, 1e-5);
}

TEST(EvalAte, ConstantOffsetIsRemovedByTheAlignment) {
  const Trajectory gt = SmoothPath(300);
  const AteResult ate = ComputeAte(gt, Offset(gt, [](std::size_t) { return Eigen::Vector3d(0.3, -1.0, 2.0); }),
                                   20 * kMs);
  EXPECT_LT(ate.stats.rmse, 1e-9);
}

TEST(EvalAte, AssociatesOnlyWithinTheMaxDifference) {
  // 20 Hz so a 30 ms shift cannot reach the next ground-truth pose either.
  const Trajectory gt = SmoothPath(100, 50 * kMs);
  const auto shifted = [&](Timestamp shift) {
    Trajectory est = gt;
    for (StampedPose& p : est) p.t += shift;
    return est;
  };
  EXPECT_EQ(ComputeAte(gt, shifted(19 * kMs), 20 * kMs).stats.count, gt.size());
  EXPECT_EQ(ComputeAte(gt, shifted(-19 * kMs), 20 * kMs).stats.count, gt.size());
  try {
    ComputeAte(gt, shifted(21 * kMs), 20 * kMs, "gt.txt", "est.txt");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no pose of est.txt is within 0.02 s of one in gt.txt"), std::string::npos)
        << e.what();
  }
}

TEST(EvalAte, RejectsEmptyAndTooFewPairs) {
  const Trajectory gt = SmoothPath(10);
  EXPECT_THROW(ComputeAte(gt, {}, 20 * kMs), InputError);
  EXPECT_THROW(ComputeAte({}, gt, 20 * kMs), InputError);
  const Trajectory two(gt.begin(), gt.begin() + 2);
  EXPECT_THROW(ComputeAte(gt, two, 20 * kMs), InputError);
  const Trajectory three(gt.begin(), gt.begin() + 3);
  EXPECT_EQ(ComputeAte(gt, three, 20 * kMs).stats.count, 3u);
}

// A part measured at the alignment fitted on another keeps the offset between them,
// which a fit of its own would remove; one pair is enough.
TEST(EvalAte, AtAGivenAlignmentTheOffsetStays) {
  const Trajectory gt = SmoothPath(300);
  const Trajectory first(gt.begin(), gt.begin() + 150);
  const Trajectory second = Offset(Trajectory(gt.begin() + 150, gt.end()),
                                   [](std::size_t) { return Eigen::Vector3d(0.0, 0.03, 0.04); });
  const SE3 T_gt_est = ComputeAte(gt, first, 20 * kMs).T_gt_est;
  const AteResult at = ComputeAteAt(gt, second, T_gt_est, 20 * kMs);
  EXPECT_EQ(at.stats.count, second.size());
  EXPECT_NEAR(at.stats.rmse, 0.05, 1e-9);
  EXPECT_LT(ComputeAte(gt, second, 20 * kMs).stats.rmse, 1e-9);
  EXPECT_NEAR(ComputeAteAt(gt, Trajectory(second.begin(), second.begin() + 1), T_gt_est, 20 * kMs).stats.rmse, 0.05,
              1e-9);
  EXPECT_THROW(ComputeAteAt(gt, {}, T_gt_est, 20 * kMs), InputError);
}

}  // namespace
}  // namespace sgslam::eval
