// Motion-only BA on synthetic scenes: accuracy from a perturbed start, outlier
// classification, tiny inputs, determinism.
#include "sgslam/optim/pose_optimizer.h"

#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <random>

#include "sgslam/optim/se3_manifold.h"

namespace sgslam::optim {
namespace {

const Intrinsics kK{525.0, 525.0, 319.5, 239.5, 40.0};
constexpr double kPi = 3.14159265358979323846;

struct Scene {
  SE3 T_c_w;
  std::vector<PoseObservation> obs;
  std::vector<bool> outlier;  // ground truth: a random pixel, not the projection
};

// n points 0.8..6 m in front of the camera; noise of sigma(level) = 1.2^level px
// (1 px at level 0, ORB-SLAM2's scale factor), a fraction replaced by random pixels.
Scene MakeScene(int n, double outlier_fraction, bool stereo, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0, 1);
  std::normal_distribution<double> N(0, 1);
  Scene s;
  s.T_c_w = SE3(so3::Exp(Eigen::Vector3d(0.3, -0.5, 0.2)), Eigen::Vector3d(0.4, -0.2, 1.1));
  const SE3 T_w_c = s.T_c_w.Inverse();
  for (int i = 0; i < n; ++i) {
    const double u = 640 * U(rng), v = 480 * U(rng), z = 0.8 + 5.2 * U(rng);
    const Eigen::Vector3d p_c((u - kK.cx) * z / kK.fx, (v - kK.cy) * z / kK.fy, z);
    const int level = static_cast<int>(4 * U(rng));
    const double sigma = std::pow(1.2, level);
    PoseObservation o;
    o.p_w = T_w_c * p_c;
    o.inv_sigma2 = 1.0 / (sigma * sigma);
    const bool bad = U(rng) < outlier_fraction;
    o.uv = bad ? Eigen::Vector2d(640 * U(rng), 480 * U(rng)) : Eigen::Vector2d(u + sigma * N(rng), v + sigma * N(rng));
    if (stereo) o.u_right = bad ? o.uv.x() - kK.bf / (0.8 + 5.2 * U(rng)) : u - kK.bf / z + sigma * N(rng);
    s.obs.push_back(o);
    s.outlier.push_back(bad);
  }
  return s;
}

SE3 Perturb(const SE3& T, double metres, double degrees, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> N(0, 1);
  const Eigen::Vector3d dt = Eigen::Vector3d(N(rng), N(rng), N(rng)).normalized() * metres;
  const Eigen::Vector3d dr = Eigen::Vector3d(N(rng), N(rng), N(rng)).normalized() * degrees * kPi / 180;
  return SE3(so3::Exp(dr), dt) * T;
}

void ExpectNear(const SE3& a, const SE3& b, double metres, double degrees) {
  const SE3 d = a * b.Inverse();
  EXPECT_LT(d.translation().norm(), metres);
  EXPECT_LT(so3::Log(d.quaternion()).norm() * 180 / kPi, degrees);
}

void RunOutlierScene(bool stereo) {
  const Scene s = MakeScene(300, 0.2, stereo, stereo ? 11 : 12);
  const PoseOptimizationResult r = OptimizePose(Perturb(s.T_c_w, 0.05, 3.0, 3), s.obs, kK);
  ExpectNear(r.T_c_w, s.T_c_w, 0.01, 0.3);
  int true_out = 0, flagged = 0, true_in = 0, kept = 0;
  for (std::size_t i = 0; i < s.obs.size(); ++i) {
    if (s.outlier[i]) {
      ++true_out;
      flagged += r.inlier[i] ? 0 : 1;
    } else {
      ++true_in;
      kept += r.inlier[i] ? 1 : 0;
    }
  }
  EXPECT_GT(flagged, 0.95 * true_out);
  // The chi2 gate sits at the 95 % quantile, so by design it drops ~5 % of the
  // true inliers (those with the largest noise): kept ~ 95 % +- 1.5 %.
  EXPECT_GT(kept, 0.92 * true_in);
  EXPECT_EQ(r.inliers, static_cast<int>(std::count(r.inlier.begin(), r.inlier.end(), true)));
  std::printf("%s: outliers flagged %d/%d, inliers kept %d/%d\n", stereo ? "stereo" : "mono", flagged, true_out, kept,
              true_in);
}

TEST(PoseOptimizer, StereoWithOutliers) { RunOutlierScene(true); }
TEST(PoseOptimizer, MonoWithOutliers) { RunOutlierScene(false); }

TEST(PoseOptimizer, MixedNoiseFreeConvergesExactly) {
  Scene s = MakeScene(200, 0.0, true, 5);
  for (std::size_t i = 0; i < s.obs.size(); i += 2) s.obs[i].u_right = -1;  // half monocular
  const SE3 T = s.T_c_w;
  for (auto& o : s.obs) {  // exact measurements
    const Eigen::Vector3d p = T * o.p_w;
    o.uv = Eigen::Vector2d(kK.fx * p.x() / p.z() + kK.cx, kK.fy * p.y() / p.z() + kK.cy);
    if (o.u_right >= 0) o.u_right = o.uv.x() - kK.bf / p.z();
  }
  const PoseOptimizationResult r = OptimizePose(Perturb(T, 0.05, 3.0, 4), s.obs, kK);
  ExpectNear(r.T_c_w, T, 1e-6, 1e-5);
  EXPECT_EQ(r.inliers, 200);
}

TEST(PoseOptimizer, FewObservations) {
  const Scene s = MakeScene(8, 0.0, true, 6);
  const PoseOptimizationResult r = OptimizePose(Perturb(s.T_c_w, 0.01, 0.5, 5), s.obs, kK);
  ASSERT_EQ(r.inlier.size(), 8u);
  EXPECT_GE(r.inliers, 6);
  ExpectNear(r.T_c_w, s.T_c_w, 0.05, 1.0);

  // Two points cannot fix 6 dof: the pose comes back unchanged, still classified.
  const std::vector<PoseObservation> two(s.obs.begin(), s.obs.begin() + 2);
  const PoseOptimizationResult r2 = OptimizePose(s.T_c_w, two, kK);
  EXPECT_EQ(r2.T_c_w.translation(), s.T_c_w.translation());
  EXPECT_EQ(r2.inlier.size(), 2u);
  EXPECT_EQ(r2.inliers, static_cast<int>(std::count(r2.inlier.begin(), r2.inlier.end(), true)));

  const PoseOptimizationResult r0 = OptimizePose(s.T_c_w, {}, kK);
  EXPECT_TRUE(r0.inlier.empty());
  EXPECT_EQ(r0.inliers, 0);
}

TEST(PoseOptimizer, PointBehindCameraIsOutlier) {
  Scene s = MakeScene(50, 0.0, true, 7);
  s.obs[0].p_w = s.T_c_w.Inverse() * Eigen::Vector3d(0.1, 0.2, -2.0);
  const PoseOptimizationResult r = OptimizePose(s.T_c_w, s.obs, kK);
  EXPECT_FALSE(r.inlier[0]);
  ExpectNear(r.T_c_w, s.T_c_w, 0.01, 0.3);
}

// The optimiser hands Ceres one compressed block with the Huber kernel inside
// (PoseOnlyBatchCost); the textbook problem has one block and one HuberLoss per
// observation. From the same start both reach the same minimum: the optimiser
// stops at Ceres' default tolerances (relative cost change 1e-6), so its cost
// is within 1e-6 of the fully converged one and the pose within 0.1 mm.
TEST(PoseOptimizer, MatchesOneHuberBlockPerObservation) {
  for (const bool stereo : {true, false}) {
    Scene s = MakeScene(300, 0.15, stereo, stereo ? 21 : 22);
    const SE3 start = Perturb(s.T_c_w, 0.03, 2.0, 9);
    PoseOptimizerOptions one_round;
    one_round.rounds = 1;  // a single run keeps the kernel on
    one_round.iterations = 200;
    const PoseOptimizationResult r = OptimizePose(start, s.obs, kK, one_round);

    double x[kPoseAmbientSize];
    PoseToParams(start, x);
    SE3LeftManifold manifold;
    ceres::Problem::Options po;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    problem.AddParameterBlock(x, kPoseAmbientSize, &manifold);
    for (const PoseObservation& o : s.obs) {
      const ReprojectionMeasurement m{o.uv, o.u_right, std::sqrt(o.inv_sigma2)};
      problem.AddResidualBlock(MakePoseOnlyCost(kK, m, o.p_w), new ceres::HuberLoss(std::sqrt(stereo ? 7.815 : 5.991)),
                               x);
    }
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = 200;
    so.function_tolerance = so.gradient_tolerance = so.parameter_tolerance = 1e-14;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    ASSERT_TRUE(summary.IsSolutionUsable());
    ExpectNear(r.T_c_w, ParamsToPose(x), 1e-4, 1e-3);
    double ours = 0, x_ours[kPoseAmbientSize];
    PoseToParams(r.T_c_w, x_ours);
    std::vector<double> unused;
    ceres::Problem::EvaluateOptions eo;
    problem.Evaluate(eo, &ours, &unused, nullptr, nullptr);  // at x: the reference minimum
    const double reference = ours;
    std::copy(x_ours, x_ours + kPoseAmbientSize, x);
    problem.Evaluate(eo, &ours, &unused, nullptr, nullptr);
    EXPECT_LE(ours - reference, 1e-6 * reference) << (stereo ? "stereo" : "mono");
    EXPECT_GE(ours - reference, -1e-9 * reference) << "the reference is the minimum";
  }
}

TEST(PoseOptimizer, Deterministic) {
  const Scene s = MakeScene(400, 0.2, true, 8);
  const SE3 start = Perturb(s.T_c_w, 0.05, 3.0, 6);
  const PoseOptimizationResult a = OptimizePose(start, s.obs, kK);
  const PoseOptimizationResult b = OptimizePose(start, s.obs, kK);
  EXPECT_EQ(
      0, std::memcmp(a.T_c_w.quaternion().coeffs().data(), b.T_c_w.quaternion().coeffs().data(), 4 * sizeof(double)));
  EXPECT_EQ(0, std::memcmp(a.T_c_w.translation().data(), b.T_c_w.translation().data(), 3 * sizeof(double)));
  EXPECT_EQ(a.inlier, b.inlier);
}

}  // namespace
}  // namespace sgslam::optim
