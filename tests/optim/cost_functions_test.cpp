// Every analytic Jacobian against Ridders numerical differentiation (ambient
// and, through the manifold, tangent), and the manifold's round trips.
#include "sgslam/optim/cost_functions.h"

#include <ceres/numeric_diff_cost_function.h>
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "sgslam/optim/se3_manifold.h"

namespace sgslam::optim {
namespace {

using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
const Intrinsics kK{525.0, 520.0, 319.5, 239.5, 40.0};

SE3 RandomPose(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Vector6d xi;
  for (int i = 0; i < 6; ++i) xi[i] = n(rng);
  return SE3::Exp(xi);
}

// A world point in front of the camera T_c_w, plus a measurement near it.
void RandomObservation(std::mt19937& rng, const SE3& T_c_w, bool stereo, Eigen::Vector3d& p_w,
                       ReprojectionMeasurement& m) {
  std::uniform_real_distribution<double> xy(-1.5, 1.5), z(0.5, 8.0), px(-3.0, 3.0), level(0, 7);
  const Eigen::Vector3d p_c(xy(rng), xy(rng), z(rng));
  p_w = T_c_w.Inverse() * p_c;
  m.uv = Eigen::Vector2d(kK.fx * p_c.x() / p_c.z() + kK.cx + px(rng), kK.fy * p_c.y() / p_c.z() + kK.cy + px(rng));
  m.u_right = stereo ? m.uv.x() - kK.bf / p_c.z() + px(rng) : -1.0;
  m.sqrt_info = std::pow(1.2, -static_cast<int>(level(rng)));
}

// Residual-only adapter so Ceres' numeric differentiation sees the same function.
struct ResidualOf {
  const ceres::CostFunction* cost;
  bool operator()(const double* a, double* r) const {
    const double* p[] = {a};
    return cost->Evaluate(p, r, nullptr);
  }
  bool operator()(const double* a, const double* b, double* r) const {
    const double* p[] = {a, b};
    return cost->Evaluate(p, r, nullptr);
  }
};

// Ridders' default first step (1 % of each coordinate) can reach across the
// 1/z pole for near points; start at 0.1 %.
ceres::NumericDiffOptions RiddersOptions() {
  ceres::NumericDiffOptions o;
  o.ridders_relative_initial_step_size = 1e-3;
  return o;
}

// The poses Plus(x, +-h e_j): central differences along tangent direction j.
void PlusMinus(const SE3LeftManifold& manifold, const double* x, int j, double h, double* xp, double* xm) {
  double d[6] = {0, 0, 0, 0, 0, 0};
  d[j] = h;
  manifold.Plus(x, d, xp);
  d[j] = -h;
  manifold.Plus(x, d, xm);
}

double RelativeError(const Matrix& analytic, const Matrix& numeric) {
  return (analytic - numeric).norm() / std::max(1.0, numeric.norm());
}

// Evaluates `cost` analytically and numerically at `params`; checks each block,
// then the tangent Jacobian of the pose block against differences through Plus.
void CheckCost(const ceres::CostFunction& cost, const ceres::CostFunction& numeric, std::vector<double*> params) {
  const int nr = cost.num_residuals();
  const auto& sizes = cost.parameter_block_sizes();
  std::vector<Matrix> Ja, Jn;
  std::vector<double*> ja, jn;
  for (int s : sizes) {
    Ja.emplace_back(nr, s);
    Jn.emplace_back(nr, s);
  }
  for (std::size_t b = 0; b < sizes.size(); ++b) {
    ja.push_back(Ja[b].data());
    jn.push_back(Jn[b].data());
  }
  Eigen::VectorXd ra(nr), rn(nr);
  ASSERT_TRUE(cost.Evaluate(params.data(), ra.data(), ja.data()));
  ASSERT_TRUE(numeric.Evaluate(params.data(), rn.data(), jn.data()));
  EXPECT_LT((ra - rn).norm(), 1e-12);
  for (std::size_t b = 0; b < sizes.size(); ++b) EXPECT_LT(RelativeError(Ja[b], Jn[b]), 1e-6) << "block " << b;

  // Tangent: J_ambient * PlusJacobian against central differences of r(Plus(x, d)).
  SE3LeftManifold manifold;
  Matrix P(7, 6), Jt(nr, 6);
  manifold.PlusJacobian(params[0], P.data());
  const double h = 1e-6;
  for (int j = 0; j < 6; ++j) {
    double xp[7], xm[7];
    PlusMinus(manifold, params[0], j, h, xp, xm);
    Eigen::VectorXd rp(nr), rm(nr);
    std::vector<double*> pp = params, pm = params;
    pp[0] = xp;
    pm[0] = xm;
    cost.Evaluate(pp.data(), rp.data(), nullptr);
    cost.Evaluate(pm.data(), rm.data(), nullptr);
    Jt.col(j) = (rp - rm) / (2 * h);
  }
  EXPECT_LT(RelativeError(Ja[0] * P, Jt), 1e-6);
}

template <int N>
void CheckPoseOnly(int seed) {
  std::mt19937 rng(seed);
  for (int trial = 0; trial < 100; ++trial) {
    const SE3 T = RandomPose(rng);
    Eigen::Vector3d p_w;
    ReprojectionMeasurement m;
    RandomObservation(rng, T, N == 3, p_w, m);
    PoseOnlyReprojectionCost<N> cost(kK, m, p_w);
    ceres::NumericDiffCostFunction<ResidualOf, ceres::RIDDERS, N, 7> numeric(
        new ResidualOf{&cost}, ceres::TAKE_OWNERSHIP, N, RiddersOptions());
    double x[7];
    PoseToParams(T, x);
    CheckCost(cost, numeric, {x});
  }
}

template <int N>
void CheckBa(int seed) {
  std::mt19937 rng(seed);
  for (int trial = 0; trial < 100; ++trial) {
    const SE3 T = RandomPose(rng);
    Eigen::Vector3d p_w;
    ReprojectionMeasurement m;
    RandomObservation(rng, T, N == 3, p_w, m);
    BaReprojectionCost<N> cost(kK, m);
    ceres::NumericDiffCostFunction<ResidualOf, ceres::RIDDERS, N, 7, 3> numeric(
        new ResidualOf{&cost}, ceres::TAKE_OWNERSHIP, N, RiddersOptions());
    double x[7];
    PoseToParams(T, x);
    CheckCost(cost, numeric, {x, p_w.data()});
  }
}

TEST(CostFunctions, PoseOnlyMonoJacobian) { CheckPoseOnly<2>(1); }
TEST(CostFunctions, PoseOnlyStereoJacobian) { CheckPoseOnly<3>(2); }
TEST(CostFunctions, BaMonoJacobian) { CheckBa<2>(3); }
TEST(CostFunctions, BaStereoJacobian) { CheckBa<3>(4); }

// The batch's full residual stack. Without a kernel: its tangent Jacobian
// against central differences through Plus. With Huber kernels, half the items
// beyond delta (RandomObservation's noise is up to 3 px, delta ~1.5-2.8): the
// cost is sum rho(chi2), and J^T r (Ceres' sqrt(rho') correction) is the exact
// gradient of half of it.
TEST(CostFunctions, PoseOnlyBatchIsHuberPerObservation) {
  std::mt19937 rng(6);
  SE3LeftManifold manifold;
  int beyond = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const SE3 T = RandomPose(rng);
    std::vector<PoseOnlyBatchCost::Item> plain, robust;
    for (int i = 0; i < 30; ++i) {
      PoseOnlyBatchCost::Item it;
      RandomObservation(rng, T, i % 3 != 0, it.p_w, it.m);
      it.m.sqrt_info = 1.0;
      plain.push_back(it);
      it.huber_delta = i % 5 == 0 ? 0.0 : std::sqrt(it.m.u_right < 0 ? 5.991 : 7.815);
      robust.push_back(it);
    }
    const PoseOnlyBatchCost plain_cost(kK, plain), robust_cost(kK, robust);
    double x[7];
    PoseToParams(T, x);
    Eigen::VectorXd r;
    Eigen::MatrixXd J;
    double c = 0, expected = 0;
    ASSERT_TRUE(robust_cost.EvaluateFull(x, r, &J, &c));
    for (const auto& it : robust) {
      const double s = ReprojectionChi2(kK, it.m, T * it.p_w), d = it.huber_delta;
      expected += d > 0 && s > d * d ? 2 * d * std::sqrt(s) - d * d : s;
      beyond += d > 0 && s > d * d;
    }
    EXPECT_NEAR(c, expected, 1e-9 * expected);
    const Eigen::VectorXd gradient = J.transpose() * r;

    Eigen::VectorXd rp_, rm_;
    Eigen::MatrixXd Jp;
    ASSERT_TRUE(plain_cost.EvaluateFull(x, rp_, &Jp));
    const double h = 1e-6;
    Eigen::MatrixXd Jn(Jp.rows(), 6);
    Eigen::VectorXd gn(6);
    for (int j = 0; j < 6; ++j) {
      double xp[7], xm[7];
      PlusMinus(manifold, x, j, h, xp, xm);
      Eigen::VectorXd rp, rm;
      ASSERT_TRUE(plain_cost.EvaluateFull(xp, rp, nullptr));
      ASSERT_TRUE(plain_cost.EvaluateFull(xm, rm, nullptr));
      Jn.col(j) = (rp - rm) / (2 * h);
      double cp = 0, cm = 0;
      ASSERT_TRUE(robust_cost.EvaluateFull(xp, rp, nullptr, &cp));
      ASSERT_TRUE(robust_cost.EvaluateFull(xm, rm, nullptr, &cm));
      gn[j] = 0.5 * (cp - cm) / (2 * h);
    }
    EXPECT_LT((Jp - Jn).norm() / std::max(1.0, Jn.norm()), 1e-6);
    EXPECT_LT((gradient - gn).norm() / std::max(1.0, gn.norm()), 1e-5);
  }
  EXPECT_GT(beyond, 100) << "the test must reach the Huber region";
}

// The 7 rows Ceres sees stand for the full stack: squared norm = the Huber
// cost, and through the manifold the same J^T J and J^T r; without Jacobians
// [sqrt(cost), 0...].
TEST(CostFunctions, PoseOnlyBatchCompressionKeepsNormalEquations) {
  std::mt19937 rng(7);
  SE3LeftManifold manifold;
  for (int trial = 0; trial < 20; ++trial) {
    const SE3 T = RandomPose(rng);
    std::vector<PoseOnlyBatchCost::Item> items;
    for (int i = 0; i < 40; ++i) {
      PoseOnlyBatchCost::Item it;
      RandomObservation(rng, T, i % 4 != 0, it.p_w, it.m);
      it.huber_delta = std::sqrt(7.815);
      items.push_back(it);
    }
    const PoseOnlyBatchCost cost(kK, items);
    ASSERT_EQ(cost.num_residuals(), 7);
    double x[7];
    PoseToParams(T, x);
    Eigen::VectorXd r;
    Eigen::MatrixXd J;
    double c = 0;
    ASSERT_TRUE(cost.EvaluateFull(x, r, &J, &c));
    Eigen::Matrix<double, 7, 1> rc, r0;
    Eigen::Matrix<double, 7, 7, Eigen::RowMajor> Ja;
    const double* params[] = {x};
    double* jac[] = {Ja.data()};
    ASSERT_TRUE(cost.Evaluate(params, rc.data(), jac));
    ASSERT_TRUE(cost.Evaluate(params, r0.data(), nullptr));
    Eigen::Matrix<double, 7, 6, Eigen::RowMajor> P;
    manifold.PlusJacobian(x, P.data());
    const Eigen::Matrix<double, 7, 6> Jt = Ja * P;
    const Eigen::MatrixXd H = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    EXPECT_NEAR(rc.squaredNorm(), c, 1e-9 * c);
    EXPECT_NEAR(r0[0], std::sqrt(c), 1e-9 * std::sqrt(c));
    EXPECT_EQ(r0.tail<6>().norm(), 0.0);
    EXPECT_LT((Jt.transpose() * Jt - H).norm(), 1e-8 * H.norm());
    EXPECT_LT((Jt.transpose() * rc - g).norm(), 1e-8 * std::max(1.0, g.norm()));
  }
  // Too few points for a pose (H singular) and a point behind the camera: evaluation fails.
  const SE3 T;
  PoseOnlyBatchCost::Item one;
  one.p_w = Eigen::Vector3d(0.1, 0.2, 2.0);
  one.m.uv = Eigen::Vector2d(300, 200);
  double x[7], r[7], J[49];
  PoseToParams(T, x);
  const double* params[] = {x};
  double* jac[] = {J};
  EXPECT_FALSE(PoseOnlyBatchCost(kK, {one}).Evaluate(params, r, jac));
  PoseOnlyBatchCost::Item behind = one;
  behind.p_w.z() = -2.0;
  EXPECT_FALSE(PoseOnlyBatchCost(kK, {one, behind}).Evaluate(params, r, nullptr));
}

TEST(CostFunctions, ResidualMatchesProjectionAndChi2) {
  const SE3 T(so3::Exp(Eigen::Vector3d(0.1, -0.2, 0.3)), Eigen::Vector3d(0.2, 0.1, -0.3));
  const Eigen::Vector3d p_c(0.4, -0.3, 2.0), p_w = T.Inverse() * p_c;
  const double u = kK.fx * 0.2 + kK.cx, v = kK.fy * -0.15 + kK.cy;
  const ReprojectionMeasurement m{Eigen::Vector2d(u + 1.0, v - 2.0), u - kK.bf / 2.0 + 0.5, 0.5};
  std::unique_ptr<ceres::CostFunction> cost(MakePoseOnlyCost(kK, m, p_w));
  ASSERT_EQ(cost->num_residuals(), 3);
  double x[7], r[3];
  PoseToParams(T, x);
  const double* params[] = {x};
  ASSERT_TRUE(cost->Evaluate(params, r, nullptr));
  EXPECT_NEAR(r[0], -0.5, 1e-9);
  EXPECT_NEAR(r[1], 1.0, 1e-9);
  EXPECT_NEAR(r[2], -0.25, 1e-9);
  EXPECT_NEAR(ReprojectionChi2(kK, m, p_c), 0.25 + 1.0 + 0.0625, 1e-9);
  // Behind the camera: the evaluation fails and the chi2 is infinite.
  const ReprojectionMeasurement mono{m.uv, -1.0, 1.0};
  EXPECT_TRUE(std::isinf(ReprojectionChi2(kK, mono, Eigen::Vector3d(0, 0, -1))));
  BaMonoCost ba(kK, mono);
  const Eigen::Vector3d behind = T.Inverse() * Eigen::Vector3d(0.1, 0.1, -1.0);
  const double* ba_params[] = {x, behind.data()};
  EXPECT_FALSE(ba.Evaluate(ba_params, r, nullptr));
}

TEST(SE3LeftManifold, RoundTripsAndJacobians) {
  std::mt19937 rng(5);
  SE3LeftManifold manifold;
  for (int trial = 0; trial < 200; ++trial) {
    const SE3 X = RandomPose(rng), Y = RandomPose(rng);
    double x[7], y[7], d[6], back[7];
    PoseToParams(X, x);
    PoseToParams(Y, y);
    // Plus(x, Minus(y, x)) == y (as a rotation: q and -q are the same pose).
    ASSERT_TRUE(manifold.Minus(y, x, d));
    ASSERT_TRUE(manifold.Plus(x, d, back));
    const SE3 B = ParamsToPose(back);
    EXPECT_LT(std::abs(std::abs(B.quaternion().dot(Y.quaternion())) - 1.0), 1e-12);
    EXPECT_LT((B.translation() - Y.translation()).norm(), 1e-9);
    // Minus(Plus(x, delta), x) == delta for a small delta.
    const Vector6d delta = 0.5 * Y.Log() / std::max(1.0, Y.Log().norm());
    ASSERT_TRUE(manifold.Plus(x, delta.data(), back));
    ASSERT_TRUE(manifold.Minus(back, x, d));
    EXPECT_LT((Eigen::Map<Vector6d>(d) - delta).norm(), 1e-9);

    // PlusJacobian and MinusJacobian against central differences; their product is I.
    Matrix P(7, 6), M(6, 7), Pn(7, 6), Mn(6, 7);
    manifold.PlusJacobian(x, P.data());
    manifold.MinusJacobian(x, M.data());
    const double h = 1e-6;
    for (int j = 0; j < 6; ++j) {
      double xp[7], xm[7];
      PlusMinus(manifold, x, j, h, xp, xm);
      for (int i = 0; i < 7; ++i) Pn(i, j) = (xp[i] - xm[i]) / (2 * h);
    }
    for (int j = 0; j < 7; ++j) {
      double yp[7], ym[7], dp[6], dm[6];
      std::copy(x, x + 7, yp);
      std::copy(x, x + 7, ym);
      yp[j] += h;
      ym[j] -= h;
      manifold.Minus(yp, x, dp);
      manifold.Minus(ym, x, dm);
      for (int i = 0; i < 6; ++i) Mn(i, j) = (dp[i] - dm[i]) / (2 * h);
    }
    EXPECT_LT(RelativeError(P, Pn), 1e-8);
    // Minus normalises the quaternion: only the tangential part must agree.
    EXPECT_LT(RelativeError(M * P, Mn * P), 1e-8);
    EXPECT_LT((M * P - Matrix::Identity(6, 6)).norm(), 1e-12);
  }
}

}  // namespace
}  // namespace sgslam::optim
