// The pose graph: its edge Jacobian against central differences through the
// manifold, a drifted loop closed by one loop edge, weights, and degenerate graphs.
#include "sgslam/optim/pose_graph.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sgslam/geometry/rigid.h"
#include "sgslam/optim/se3_manifold.h"

namespace sgslam::optim {
namespace {

constexpr double kDeg = M_PI / 180.0;
using RowMajor67 = Eigen::Matrix<double, 6, 7, Eigen::RowMajor>;
using RowMajor76 = Eigen::Matrix<double, 7, 6, Eigen::RowMajor>;

SE3 RandomPose(std::mt19937& rng, double scale) {
  std::normal_distribution<double> n(0.0, scale);
  Vector6d xi;
  for (int i = 0; i < 6; ++i) xi[i] = n(rng);
  return SE3::Exp(xi);
}

double TranslationError(const SE3& a, const SE3& b) { return (a.translation() - b.translation()).norm(); }
double RotationErrorDeg(const SE3& a, const SE3& b) {
  return so3::Log(a.quaternion().conjugate() * b.quaternion()).norm() / kDeg;
}

// Tangent Jacobian of block k: the analytic one times PlusJacobian against
// central differences of r(Plus(x_k, +-h e_j)). Residuals up to ~2 rad and 2 m,
// so the exact inverse left Jacobian of SE(3) matters.
TEST(PoseGraph, EdgeJacobianMatchesNumericalDifferences) {
  std::mt19937 rng(1);
  const SE3LeftManifold manifold;
  for (int trial = 0; trial < 200; ++trial) {
    const SE3 T_i = RandomPose(rng, 1.0), T_j = RandomPose(rng, 1.0);
    // A measurement near the truth for half the trials (small residuals, the
    // Taylor branch), far from it for the rest.
    const SE3 noise = RandomPose(rng, trial % 2 == 0 ? 1e-3 : 0.7);
    const RelativePoseCost cost(noise * T_i * T_j.Inverse(), (Vector6d() << 2, 2, 2, 1, 1, 1).finished());
    double x[2][7];
    PoseToParams(T_i, x[0]);
    PoseToParams(T_j, x[1]);
    const double* params[2] = {x[0], x[1]};
    RowMajor67 J[2];
    double* jac[2] = {J[0].data(), J[1].data()};
    Vector6d r;
    ASSERT_TRUE(cost.Evaluate(params, r.data(), jac));
    for (int k = 0; k < 2; ++k) {
      RowMajor76 P;
      manifold.PlusJacobian(x[k], P.data());
      Eigen::Matrix<double, 6, 6> Jn;
      const double h = 1e-6;
      for (int c = 0; c < 6; ++c) {
        double d[6] = {0, 0, 0, 0, 0, 0}, xp[2][7], xm[2][7];
        std::copy(&x[0][0], &x[0][0] + 14, &xp[0][0]);
        std::copy(&x[0][0], &x[0][0] + 14, &xm[0][0]);
        d[c] = h;
        manifold.Plus(x[k], d, xp[k]);
        d[c] = -h;
        manifold.Plus(x[k], d, xm[k]);
        const double* pp[2] = {xp[0], xp[1]};
        const double* pm[2] = {xm[0], xm[1]};
        Vector6d rp, rm;
        cost.Evaluate(pp, rp.data(), nullptr);
        cost.Evaluate(pm, rm.data(), nullptr);
        Jn.col(c) = (rp - rm) / (2 * h);
      }
      const Eigen::Matrix<double, 6, 6> Ja = J[k] * P;
      EXPECT_LT((Ja - Jn).norm() / std::max(1.0, Jn.norm()), 1e-7) << "trial " << trial << " block " << k;
    }
  }
}

// 100 keyframes on a 3 m circle, camera looking along it, height wobbling.
std::vector<SE3> CircleTruth(int n) {
  std::vector<SE3> T_w_c;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n;
    const Eigen::Vector3d C(3 * std::cos(a), 0.2 * std::sin(3 * a), 3 * std::sin(a));
    // Camera z along the tangent, y down (world y up is -y here), rotated about y.
    const Eigen::Quaterniond q(Eigen::AngleAxisd(-a, Eigen::Vector3d::UnitY()));
    T_w_c.push_back(SE3(q, C));
  }
  return T_w_c;
}

struct Loop {
  std::vector<SE3> truth;  // T_w_c
  PoseGraphProblem graph;
};

// Odometry from the truth with a constant bias and small noise; nodes chained
// from it, the first at the truth and fixed; one loop edge (last -> first) from
// the truth. The bias (a yaw rate and a vertical velocity, as a miscalibrated
// sensor gives) drifts the end by ~0.55 m and 5 deg. It is what one loop edge can
// see: a body-frame bias in the circle's plane sums to ~0 around it, and a random
// walk leaves a Brownian bridge that no single edge removes.
Loop MakeLoop(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Loop s{CircleTruth(n), {}};
  Vector6d bias;
  bias << 0, 0.005, 0, 0, 5.0 / n * kDeg, 0;
  SE3 T_w_c = s.truth[0];
  s.graph.nodes.push_back({0, T_w_c.Inverse(), true});
  for (int k = 0; k + 1 < n; ++k) {
    Vector6d xi = bias;
    for (int i = 0; i < 6; ++i) xi[i] += (i < 3 ? 0.001 : 0.01 * kDeg) * g(rng);
    const SE3 odo = s.truth[k].Inverse() * s.truth[k + 1] * SE3::Exp(xi);  // T_ck_ck+1
    T_w_c = T_w_c * odo;
    s.graph.nodes.push_back({static_cast<std::uint64_t>(k + 1), T_w_c.Inverse(), false});
    s.graph.edges.push_back({static_cast<std::uint64_t>(k), static_cast<std::uint64_t>(k + 1), odo});
  }
  s.graph.edges.push_back({static_cast<std::uint64_t>(n - 1), 0, s.truth[n - 1].Inverse() * s.truth[0]});
  return s;
}

// RMSE of the camera centres after Horn's alignment (TUM's ATE).
double Ate(const std::vector<SE3>& truth_T_w_c, const std::vector<SE3>& T_c_w) {
  std::vector<Eigen::Vector3d> est, gt;
  for (std::size_t k = 0; k < T_c_w.size(); ++k) {
    est.push_back(T_c_w[k].Inverse().translation());
    gt.push_back(truth_T_w_c[k].translation());
  }
  const SE3 T_gt_est = geometry::AlignRigid(est, gt);
  double sum = 0;
  for (std::size_t k = 0; k < est.size(); ++k) sum += (T_gt_est * est[k] - gt[k]).squaredNorm();
  return std::sqrt(sum / est.size());
}

// The relative pose of the last camera to the first, T_c_last_c0.
SE3 EndToStart(const std::vector<SE3>& T_c_w) { return T_c_w.back() * T_c_w.front().Inverse(); }

TEST(PoseGraph, OneLoopEdgeRemovesTheDrift) {
  const Loop s = MakeLoop(100, 2);
  std::vector<SE3> before;
  for (const PoseGraphNode& node : s.graph.nodes) before.push_back(node.T_c_w);
  const SE3 end_truth = s.truth.back().Inverse() * s.truth.front();
  // The drift the loop edge has to close: ~0.5 m and ~5 deg.
  const SE3 drift_end = s.truth.back().Inverse() * before.back().Inverse();
  EXPECT_GT(drift_end.translation().norm(), 0.4);
  EXPECT_GT(so3::Log(drift_end.quaternion()).norm(), 4 * kDeg);

  const PoseGraphResult r = OptimizePoseGraph(s.graph);
  ASSERT_TRUE(r.success);
  ASSERT_EQ(r.T_c_w.size(), s.graph.nodes.size());
  EXPECT_EQ(r.invalid_edges, 0);
  EXPECT_LE(r.iterations, 20);
  EXPECT_LT(r.final_cost, 0.01 * r.initial_cost);
  EXPECT_LT(TranslationError(EndToStart(r.T_c_w), end_truth), 0.01);
  // The loop edge keeps ~1 / (n + 1) of the drift, plus its share of the noise.
  EXPECT_LT(RotationErrorDeg(EndToStart(r.T_c_w), end_truth), 0.25);
  const double ate_before = Ate(s.truth, before), ate_after = Ate(s.truth, r.T_c_w);
  EXPECT_GT(ate_before, 5 * ate_after) << ate_before << " -> " << ate_after;
  // The fixed node stays put, exactly.
  EXPECT_EQ(r.T_c_w[0].matrix(), s.graph.nodes[0].T_c_w.matrix());
}

TEST(PoseGraph, EqualInputsGiveEqualResults) {
  const Loop s = MakeLoop(60, 3);
  const PoseGraphResult a = OptimizePoseGraph(s.graph), b = OptimizePoseGraph(s.graph);
  ASSERT_EQ(a.T_c_w.size(), b.T_c_w.size());
  for (std::size_t k = 0; k < a.T_c_w.size(); ++k) EXPECT_EQ(a.T_c_w[k].matrix(), b.T_c_w[k].matrix());
  EXPECT_EQ(a.final_cost, b.final_cost);
  EXPECT_EQ(a.iterations, b.iterations);
}

TEST(PoseGraph, AHeavierLoopEdgeIsMetMoreClosely) {
  Loop s = MakeLoop(100, 4);
  const SE3 end_truth = s.truth.back().Inverse() * s.truth.front();
  const double light = TranslationError(EndToStart(OptimizePoseGraph(s.graph).T_c_w), end_truth);
  s.graph.edges.back().weight = 100;
  const double heavy = TranslationError(EndToStart(OptimizePoseGraph(s.graph).T_c_w), end_truth);
  EXPECT_LT(heavy, 0.1 * light);
}

TEST(PoseGraph, WeightsScaleTheCost) {
  // One edge off by (rho, phi) = Log(T_err): cost = weight / 2 (w_t |rho|^2 + |phi|^2).
  const SE3 T_err = SE3::Exp((Vector6d() << 0.1, -0.2, 0.05, 0.02, 0.03, -0.01).finished());
  const Vector6d xi = T_err.Log();
  PoseGraphProblem pb;
  pb.nodes = {{7, SE3(), true}, {9, T_err, false}};
  pb.edges = {{7, 9, SE3(), 3.0}};  // measured identity, so r = Log(T_c7_w T_c9_w^-1) = -xi
  const PoseGraphResult r = OptimizePoseGraph(pb, {.iterations = 20, .translation_weight = 4.0});
  const double expected = 3.0 / 2 * (4.0 * xi.head<3>().squaredNorm() + xi.tail<3>().squaredNorm());
  EXPECT_NEAR(r.initial_cost, expected, 1e-12);
  EXPECT_LT(r.final_cost, 1e-15);
  EXPECT_LT(TranslationError(r.T_c_w[1], SE3()), 1e-6);
}

TEST(PoseGraph, DegenerateGraphsDoNotCrash) {
  // A single fixed node; a graph without edges; a node without edges stays put;
  // an edge to an unknown node or from a node to itself is left out.
  std::mt19937 rng(5);
  const SE3 A = RandomPose(rng, 1.0), B = RandomPose(rng, 1.0), C = RandomPose(rng, 1.0);
  PoseGraphResult r = OptimizePoseGraph({{{1, A, true}}, {}});
  ASSERT_EQ(r.T_c_w.size(), 1u);
  EXPECT_EQ(r.T_c_w[0].matrix(), A.matrix());
  EXPECT_TRUE(r.success);

  r = OptimizePoseGraph({{{1, A, false}, {2, B, false}}, {}});
  ASSERT_EQ(r.T_c_w.size(), 2u);
  EXPECT_EQ(r.T_c_w[1].matrix(), B.matrix());
  EXPECT_TRUE(OptimizePoseGraph({}).T_c_w.empty());

  const SE3 measured = RandomPose(rng, 0.1) * A * B.Inverse();
  r = OptimizePoseGraph(
      {{{1, A, false}, {2, B, false}, {3, C, false}}, {{1, 2, measured}, {2, 2, SE3()}, {2, 8, SE3()}}});
  ASSERT_TRUE(r.success);
  EXPECT_EQ(r.invalid_edges, 2);
  EXPECT_EQ(r.T_c_w[0].matrix(), A.matrix());  // no node fixed: the smallest id holds the gauge
  EXPECT_EQ(r.T_c_w[2].matrix(), C.matrix());  // no edge: unchanged
  EXPECT_LT(TranslationError(r.T_c_w[0] * r.T_c_w[1].Inverse(), measured), 1e-6);
}

}  // namespace
}  // namespace sgslam::optim
