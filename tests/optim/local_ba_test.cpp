// Local BA on synthetic keyframes around a point cloud: convergence to the noise
// level and the true poses, outlier flags, abort, degenerate inputs, determinism.
#include "sgslam/optim/local_ba.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>

namespace sgslam::optim {
namespace {

const Intrinsics kK{525.0, 525.0, 319.5, 239.5, 40.0};
constexpr double kPi = 3.14159265358979323846;

struct Scene {
  BaProblem truth, start;
  std::vector<bool> gross;  // ground-truth outliers per observation
};

// Keyframes on an arc looking at a 2 x 1.6 x 2 m cloud 3 m ahead; the first
// and last are fixed (older keyframes that see the local points). Noise
// 1.2^level px (levels 0-1), `gross` random pixels, perturbed free poses
// (3 cm, 1 deg) and points (5 cm).
Scene MakeScene(int n_kf, int n_pt, double gross_fraction, double stereo_fraction, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0, 1);
  std::normal_distribution<double> N(0, 1);
  Scene s;
  s.truth.intrinsics = kK;
  const Eigen::Vector3d target(0, 0, 3);
  for (int k = 0; k < n_kf; ++k) {
    const double a = -0.4 + 0.8 * k / std::max(1, n_kf - 1);
    const Eigen::Vector3d C(3 * std::sin(a), 0.2 * N(rng), 3 - 3 * std::cos(a));
    const Eigen::Vector3d z = (target - C).normalized();
    const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
    Eigen::Matrix3d R_w_c;
    R_w_c << x, z.cross(x), z;
    s.truth.keyframes.push_back(
        {static_cast<std::uint64_t>(100 + k), SE3(R_w_c, C).Inverse(), k == 0 || k == n_kf - 1});
  }
  for (int p = 0; p < n_pt; ++p)
    s.truth.points.push_back(
        {static_cast<std::uint64_t>(p), target + Eigen::Vector3d(2 * U(rng) - 1, 1.6 * U(rng) - 0.8, 2 * U(rng) - 1)});
  for (int p = 0; p < n_pt; ++p) {
    for (int k = 0; k < n_kf; ++k) {
      const Eigen::Vector3d pc = s.truth.keyframes[k].T_c_w * s.truth.points[p].p_w;
      const Eigen::Vector2d uv(kK.fx * pc.x() / pc.z() + kK.cx, kK.fy * pc.y() / pc.z() + kK.cy);
      if (uv.x() < 0 || uv.x() > 640 || uv.y() < 0 || uv.y() > 480 || U(rng) < 0.2) continue;
      const double sigma = U(rng) < 0.5 ? 1.0 : 1.2;
      BaObservation o{k, p, uv + sigma * Eigen::Vector2d(N(rng), N(rng)), -1, 1 / (sigma * sigma)};
      if (U(rng) < stereo_fraction) o.u_right = uv.x() - kK.bf / pc.z() + sigma * N(rng);
      const bool bad = U(rng) < gross_fraction;
      if (bad) {
        o.uv = Eigen::Vector2d(640 * U(rng), 480 * U(rng));
        if (o.u_right >= 0) o.u_right = o.uv.x() - kK.bf / pc.z();
      }
      s.truth.observations.push_back(o);
      s.gross.push_back(bad);
    }
  }
  s.start = s.truth;
  for (auto& kf : s.start.keyframes) {
    if (kf.fixed) continue;
    const Eigen::Vector3d dt = Eigen::Vector3d(N(rng), N(rng), N(rng)).normalized() * 0.03;
    const Eigen::Vector3d dr = Eigen::Vector3d(N(rng), N(rng), N(rng)).normalized() * kPi / 180;
    kf.T_c_w = SE3(so3::Exp(dr), dt) * kf.T_c_w;
  }
  for (auto& pt : s.start.points) pt.p_w += 0.05 * Eigen::Vector3d(N(rng), N(rng), N(rng));
  return s;
}

// RMS of the whitened residual components (1 at the noise level) over the
// observations not in `skip`.
double Rms(const BaProblem& pb, const std::vector<SE3>& T, const std::vector<Eigen::Vector3d>& P,
           const std::vector<bool>& skip) {
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < pb.observations.size(); ++i) {
    if (skip[i]) continue;
    const BaObservation& o = pb.observations[i];
    const ReprojectionMeasurement m{o.uv, o.u_right, std::sqrt(o.inv_sigma2)};
    sum += ReprojectionChi2(kK, m, T[o.keyframe] * P[o.point]);
    n += o.u_right < 0 ? 2 : 3;
  }
  return std::sqrt(sum / n);
}

std::vector<SE3> Poses(const BaProblem& pb) {
  std::vector<SE3> T;
  for (const auto& kf : pb.keyframes) T.push_back(kf.T_c_w);
  return T;
}
std::vector<Eigen::Vector3d> Points(const BaProblem& pb) {
  std::vector<Eigen::Vector3d> P;
  for (const auto& p : pb.points) P.push_back(p.p_w);
  return P;
}

void ExpectConverges(double stereo_fraction, unsigned seed) {
  const Scene s = MakeScene(7, 300, 0.05, stereo_fraction, seed);
  const BaResult r = SolveLocalBa(s.start, BaOptions{});
  ASSERT_FALSE(r.aborted);
  const double before = Rms(s.start, Poses(s.start), Points(s.start), s.gross);
  const double after = Rms(s.start, r.T_c_w, r.p_w, r.outlier);  // over what the map keeps
  EXPECT_GT(before, 5.0);
  EXPECT_LT(after, 1.05);  // whitened: 1.0 is the noise level
  for (std::size_t k = 0; k < r.T_c_w.size(); ++k) {
    const SE3 T_w_c = r.T_c_w[k].Inverse(), T_w_c_true = s.truth.keyframes[k].T_c_w.Inverse();
    EXPECT_LT((T_w_c.translation() - T_w_c_true.translation()).norm(), 0.01) << "keyframe " << k;
    EXPECT_LT(so3::Log(T_w_c.quaternion().conjugate() * T_w_c_true.quaternion()).norm() * 180 / kPi, 0.3)
        << "keyframe " << k;
  }
  int gross = 0, flagged = 0, good = 0, dropped = 0;
  for (std::size_t i = 0; i < s.gross.size(); ++i) {
    gross += s.gross[i] ? 1 : 0;
    flagged += s.gross[i] && r.outlier[i] ? 1 : 0;
    good += s.gross[i] ? 0 : 1;
    dropped += !s.gross[i] && r.outlier[i] ? 1 : 0;
  }
  EXPECT_GT(flagged, 0.95 * gross);
  EXPECT_LT(dropped, 0.08 * good);  // the 95 % chi2 gate drops ~5 % by design
  EXPECT_LT(r.final_cost, r.initial_cost);
  EXPECT_GT(r.iterations, 0);
  std::printf("rms %.2f -> %.3f, gross flagged %d/%d, good dropped %d/%d, %d iterations\n", before, after, flagged,
              gross, dropped, good, r.iterations);
}

TEST(LocalBa, MixedStereoMonoConverges) { ExpectConverges(0.5, 1); }
TEST(LocalBa, MonoOnlyConverges) { ExpectConverges(0.0, 2); }
TEST(LocalBa, StereoOnlyConverges) { ExpectConverges(1.0, 3); }

TEST(LocalBa, AbortStopsEarly) {
  const Scene s = MakeScene(6, 200, 0.0, 0.5, 4);
  const BaResult now = SolveLocalBa(s.start, BaOptions{}, [] { return true; });
  EXPECT_TRUE(now.aborted);
  EXPECT_EQ(now.iterations, 0);
  for (std::size_t k = 0; k < now.T_c_w.size(); ++k)
    EXPECT_EQ(now.T_c_w[k].translation(), s.start.keyframes[k].T_c_w.translation());
  EXPECT_EQ(now.outlier.size(), s.start.observations.size());

  int polls = 0;
  const BaResult later = SolveLocalBa(s.start, BaOptions{}, [&] { return ++polls > 2; });
  EXPECT_TRUE(later.aborted);
  EXPECT_EQ(later.iterations, 2);  // progress made before the abort is kept
  EXPECT_LT(later.final_cost, later.initial_cost);
}

TEST(LocalBa, DegenerateInputs) {
  const BaResult empty = SolveLocalBa(BaProblem{}, BaOptions{});
  EXPECT_TRUE(empty.T_c_w.empty() && empty.p_w.empty() && empty.outlier.empty());

  Scene s = MakeScene(4, 50, 0.0, 0.5, 5);
  BaProblem no_obs = s.start;
  no_obs.observations.clear();
  const BaResult r1 = SolveLocalBa(no_obs, BaOptions{});
  ASSERT_EQ(r1.p_w.size(), 50u);
  EXPECT_EQ(r1.p_w[3], s.start.points[3].p_w);
  EXPECT_EQ(r1.iterations, 0);

  // Bad indices and a point behind a camera are flagged, not fatal; with every
  // keyframe fixed only the points move.
  BaProblem odd = s.start;
  for (auto& kf : odd.keyframes) kf.fixed = true;
  odd.observations.push_back({7, 0, Eigen::Vector2d(1, 1)});
  odd.observations.push_back({0, -1, Eigen::Vector2d(1, 1)});
  odd.points.push_back({999, odd.keyframes[0].T_c_w.Inverse() * Eigen::Vector3d(0, 0, -3)});
  odd.observations.push_back({0, static_cast<int>(odd.points.size()) - 1, Eigen::Vector2d(300, 200)});
  const BaResult r2 = SolveLocalBa(odd, BaOptions{});
  const std::size_t n = odd.observations.size();
  EXPECT_TRUE(r2.outlier[n - 1] && r2.outlier[n - 2] && r2.outlier[n - 3]);
  for (std::size_t k = 0; k < odd.keyframes.size(); ++k)
    EXPECT_EQ(r2.T_c_w[k].translation(), odd.keyframes[k].T_c_w.translation());
  EXPECT_LE(r2.final_cost, r2.initial_cost);

  // A point seen by one monocular observation is free along its ray: it is held.
  BaProblem lone = s.start;
  lone.points.push_back({1000, lone.keyframes[1].T_c_w.Inverse() * Eigen::Vector3d(0.1, 0.1, 3.0)});
  lone.observations.push_back({1, static_cast<int>(lone.points.size()) - 1, Eigen::Vector2d(340, 260)});
  const BaResult r4 = SolveLocalBa(lone, BaOptions{});
  EXPECT_EQ(r4.p_w.back(), lone.points.back().p_w);

  // No keyframe fixed: the gauge holds the smallest id, wherever it sits.
  BaProblem free = s.start;
  for (auto& kf : free.keyframes) kf.fixed = false;
  free.keyframes[2].id = 1;
  const BaResult r3 = SolveLocalBa(free, BaOptions{});
  EXPECT_EQ(r3.T_c_w[2].translation(), free.keyframes[2].T_c_w.translation());
  EXPECT_NE(r3.T_c_w[0].translation(), free.keyframes[0].T_c_w.translation());
}

TEST(LocalBa, Deterministic) {
  const Scene s = MakeScene(6, 200, 0.05, 0.5, 6);
  const BaResult a = SolveLocalBa(s.start, BaOptions{});
  const BaResult b = SolveLocalBa(s.start, BaOptions{});
  for (std::size_t k = 0; k < a.T_c_w.size(); ++k) {
    EXPECT_EQ(0, std::memcmp(a.T_c_w[k].quaternion().coeffs().data(), b.T_c_w[k].quaternion().coeffs().data(),
                             4 * sizeof(double)));
    EXPECT_EQ(a.T_c_w[k].translation(), b.T_c_w[k].translation());
  }
  for (std::size_t p = 0; p < a.p_w.size(); ++p) EXPECT_EQ(a.p_w[p], b.p_w[p]);
  EXPECT_EQ(a.outlier, b.outlier);
  EXPECT_EQ(a.final_cost, b.final_cost);
}

}  // namespace
}  // namespace sgslam::optim
