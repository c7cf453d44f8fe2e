// The essential graph as loop closing meets it: `nodes` keyframes on one lap of a
// 5 m circle, each joined to its next 10 (spanning tree and covisibility edges,
// measured from the drifted poses as ORB-SLAM2 takes them), and 5 x 5 loop edges
// between the last and first keyframes from the truth. The chained odometry
// drifts ~0.5 m and 5 deg over the lap. The first keyframe is fixed; ORB-SLAM2's
// 20 LM iterations at most.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "sgslam/optim/pose_graph.h"

namespace sgslam::optim {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

PoseGraphProblem MakeGraph(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<SE3> truth, drifted;  // T_w_c
  for (int k = 0; k < n; ++k) {
    const double a = 2 * 3.14159265358979323846 * k / n;
    const Eigen::Quaterniond q(Eigen::AngleAxisd(-a, Eigen::Vector3d::UnitY()));
    truth.push_back(SE3(q, Eigen::Vector3d(5 * std::cos(a), 0.3 * std::sin(2 * a), 5 * std::sin(a))));
  }
  drifted.push_back(truth[0]);
  for (int k = 0; k + 1 < n; ++k) {
    Vector6d xi;
    xi << 0.002 * g(rng), 0.5 / n + 0.002 * g(rng), 0.002 * g(rng), 0.02 * kDeg * g(rng),
        5.0 / n * kDeg + 0.02 * kDeg * g(rng), 0.02 * kDeg * g(rng);
    drifted.push_back(drifted.back() * truth[k].Inverse() * truth[k + 1] * SE3::Exp(xi));
  }
  PoseGraphProblem pb;
  for (int k = 0; k < n; ++k) pb.nodes.push_back({static_cast<std::uint64_t>(k), drifted[k].Inverse(), k == 0});
  const auto id = [](int k) { return static_cast<std::uint64_t>(k); };
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j <= i + 10 && j < n; ++j)
      pb.edges.push_back({id(i), id(j), drifted[i].Inverse() * drifted[j]});
  }
  for (int a = 0; a < 5; ++a) {
    for (int b = 0; b < 5; ++b) pb.edges.push_back({id(n - 1 - a), id(b), truth[n - 1 - a].Inverse() * truth[b]});
  }
  return pb;
}

void BM_PoseGraph(benchmark::State& state) {
  const PoseGraphProblem pb = MakeGraph(static_cast<int>(state.range(0)), 1);
  PoseGraphResult r;
  for (auto _ : state) {
    r = OptimizePoseGraph(pb);
    benchmark::DoNotOptimize(r.final_cost);
  }
  state.counters["edges"] = static_cast<double>(pb.edges.size());
  state.counters["iterations"] = r.iterations;
  state.counters["initial_cost"] = r.initial_cost;
  state.counters["final_cost"] = r.final_cost;
}
BENCHMARK(BM_PoseGraph)->ArgName("nodes")->Arg(200)->Arg(500)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace sgslam::optim
