// Motion-only BA as tracking calls it (twice per frame): a start a few cm off,
// 10 % outliers, ORB-SLAM2's 4 x 10 LM iterations. Target: < 1.5 ms for 500
// stereo observations. Also the rolling-shutter fit tracking adds once per frame
// (pose and angular velocity, 5 LM iterations on the inliers).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "sgslam/optim/pose_optimizer.h"
#include "sgslam/optim/rolling_shutter_pose.h"

namespace {

using namespace sgslam;
using namespace sgslam::optim;

const Intrinsics kK{525.0, 525.0, 319.5, 239.5, 40.0};

struct Case {
  SE3 T_start;
  std::vector<PoseObservation> obs;
};

Case MakeCase(int n, bool stereo) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> U(0, 1);
  std::normal_distribution<double> N(0, 1);
  const SE3 T_c_w(so3::Exp(Eigen::Vector3d(0.3, -0.5, 0.2)), Eigen::Vector3d(0.4, -0.2, 1.1));
  const SE3 T_w_c = T_c_w.Inverse();
  Case c;
  c.T_start = SE3(so3::Exp(Eigen::Vector3d(0.01, -0.015, 0.01)), Eigen::Vector3d(0.02, 0.01, -0.015)) * T_c_w;
  for (int i = 0; i < n; ++i) {
    const double u = 640 * U(rng), v = 480 * U(rng), z = 0.8 + 5.2 * U(rng);
    const double sigma = std::pow(1.2, static_cast<int>(4 * U(rng)));
    PoseObservation o;
    o.p_w = T_w_c * Eigen::Vector3d((u - kK.cx) * z / kK.fx, (v - kK.cy) * z / kK.fy, z);
    o.inv_sigma2 = 1.0 / (sigma * sigma);
    const bool bad = U(rng) < 0.1;
    o.uv = bad ? Eigen::Vector2d(640 * U(rng), 480 * U(rng)) : Eigen::Vector2d(u + sigma * N(rng), v + sigma * N(rng));
    if (stereo) o.u_right = (bad ? o.uv.x() : u) - kK.bf / z + sigma * N(rng);
    c.obs.push_back(o);
  }
  return c;
}

void BM_OptimizePose(benchmark::State& state) {
  const Case c = MakeCase(static_cast<int>(state.range(0)), state.range(1) != 0);
  int inliers = 0;
  for (auto _ : state) {
    const PoseOptimizationResult r = OptimizePose(c.T_start, c.obs, kK);
    inliers = r.inliers;
    benchmark::DoNotOptimize(r);
  }
  state.counters["inliers"] = inliers;
}
BENCHMARK(BM_OptimizePose)
    ->ArgNames({"obs", "stereo"})
    ->Args({500, 1})
    ->Args({500, 0})
    ->Args({300, 1})
    ->Args({1000, 1})
    ->Unit(benchmark::kMicrosecond);

void BM_OptimizePoseAndAngularVelocity(benchmark::State& state) {
  const Case c = MakeCase(static_cast<int>(state.range(0)), true);
  std::vector<double> row_time;
  for (const PoseObservation& o : c.obs) row_time.push_back((o.uv.y() / 480 - 0.5) * 0.03);
  for (auto _ : state) {
    const RollingShutterPoseResult r = OptimizePoseAndAngularVelocity(c.T_start, c.obs, row_time, kK);
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_OptimizePoseAndAngularVelocity)->ArgNames({"obs"})->Arg(300)->Arg(500)->Unit(benchmark::kMicrosecond);

}  // namespace
