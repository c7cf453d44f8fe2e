// Local bundle adjustment at the size local mapping meets on TUM fr1_rpy
// (stats.json: median 56 keyframes, ~2500 points per BA): 25 free and 31 fixed
// keyframes on an arc around a 4 x 2 x 3 m cloud, each point seen by ~8 of
// them, 80 % of the observations with depth, 1.2^level px noise, 5 % gross
// outliers, poses perturbed by 3 cm / 1 deg and points by 5 cm. ORB-SLAM2's
// 5 robust + 10 plain LM iterations.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "sgslam/optim/local_ba.h"

namespace sgslam::optim {
namespace {

const Intrinsics kK{517.3, 516.5, 318.6, 255.3, 40.0};

BaProblem MakeProblem(int free_kf, int fixed_kf, int points, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0, 1);
  std::normal_distribution<double> N(0, 1);
  BaProblem pb;
  pb.intrinsics = kK;
  const int n_kf = free_kf + fixed_kf;
  const Eigen::Vector3d target(0, 0, 3);
  std::vector<SE3> truth;
  for (int k = 0; k < n_kf; ++k) {
    const double a = -0.5 + 1.0 * k / std::max(1, n_kf - 1);
    const Eigen::Vector3d C(2.5 * std::sin(a), 0.2 * N(rng), 3 - 2.5 * std::cos(a));
    const Eigen::Vector3d z = (target - C).normalized();
    const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
    Eigen::Matrix3d R_w_c;
    R_w_c << x, z.cross(x), z;
    truth.push_back(SE3(R_w_c, C).Inverse());
    // The newest keyframes are free, as in local mapping.
    pb.keyframes.push_back({static_cast<std::uint64_t>(k), truth.back(), k < fixed_kf});
  }
  std::vector<Eigen::Vector3d> p_true;
  for (int p = 0; p < points; ++p) {
    p_true.push_back(target + Eigen::Vector3d(4 * U(rng) - 2, 2 * U(rng) - 1, 3 * U(rng) - 1.5));
    const Eigen::Vector3d noise = 0.05 * Eigen::Vector3d(N(rng), N(rng), N(rng));
    pb.points.push_back({static_cast<std::uint64_t>(p), p_true.back() + noise});
  }
  for (int p = 0; p < points; ++p) {
    for (int k = 0; k < n_kf; ++k) {
      const Eigen::Vector3d pc = truth[k] * p_true[p];
      const Eigen::Vector2d uv(kK.fx * pc.x() / pc.z() + kK.cx, kK.fy * pc.y() / pc.z() + kK.cy);
      if (pc.z() < 0.3 || uv.x() < 0 || uv.x() > 640 || uv.y() < 0 || uv.y() > 480 || U(rng) > 0.16) continue;
      const double sigma = std::pow(1.2, static_cast<int>(4 * U(rng)));
      BaObservation o{k, p, uv + sigma * Eigen::Vector2d(N(rng), N(rng)), -1, 1 / (sigma * sigma)};
      if (U(rng) < 0.8) o.u_right = uv.x() - kK.bf / pc.z() + sigma * N(rng);
      if (U(rng) < 0.05) o.uv = Eigen::Vector2d(640 * U(rng), 480 * U(rng));
      pb.observations.push_back(o);
    }
  }
  for (auto& kf : pb.keyframes) {
    if (kf.fixed) continue;
    const Eigen::Vector3d dt = Eigen::Vector3d(N(rng), N(rng), N(rng)).normalized() * 0.03;
    const Eigen::Vector3d dr = Eigen::Vector3d(N(rng), N(rng), N(rng)).normalized() * (3.14159265 / 180);
    kf.T_c_w = SE3(so3::Exp(dr), dt) * kf.T_c_w;
  }
  return pb;
}

void BM_LocalBa(benchmark::State& state) {
  const BaProblem pb = MakeProblem(25, 31, static_cast<int>(state.range(0)), 1);
  BaResult r;
  for (auto _ : state) {
    r = SolveLocalBa(pb, BaOptions{});
    benchmark::DoNotOptimize(r.final_cost);
  }
  state.counters["observations"] = static_cast<double>(pb.observations.size());
  state.counters["iterations"] = r.iterations;
  state.counters["final_cost"] = r.final_cost;
}
BENCHMARK(BM_LocalBa)->ArgName("points")->Arg(2500)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace sgslam::optim
