// Dynamic feature rejection (Algorithm 1) on 1000 keypoints of a 640x480 synthetic
// walkers frame pair: the whole rejection and its stages.
#include <benchmark/benchmark.h>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "sgslam/dynamic/algorithm1.h"
#include "sgslam/synth/sequence.h"

namespace sgslam::dynamic {
namespace {

struct Data {
  cv::Mat prev, cur;
  std::vector<cv::KeyPoint> keys;
  std::vector<Detection> detections;
  DepthCheckInput depth;
};

const Data& Get() {
  static const Data d = [] {
    const synth::SynthSequence seq("walkers", 1, 100);
    const synth::RenderedFrame a = seq.Render(60), b = seq.Render(61);
    Data out;
    cv::cvtColor(a.bgr, out.prev, cv::COLOR_BGR2GRAY);
    cv::cvtColor(b.bgr, out.cur, cv::COLOR_BGR2GRAY);
    cv::ORB::create(1000, 1.2f, 8, 19, 0, 2, cv::ORB::HARRIS_SCORE, 31, 7)->detect(out.cur, out.keys);
    out.keys.resize(std::min<size_t>(out.keys.size(), 1000));
    out.detections = synth::GroundTruthDetections(b, seq.scene());
    const synth::Intrinsics& K = seq.intrinsics();
    out.depth = {a.depth, b.depth, 1.0, {K.fx, K.fy, K.cx, K.cy}, b.T_w_c.Inverse() * a.T_w_c, {}};
    return out;
  }();
  return d;
}

double Weight(const std::string& name) { return name == "person" ? 5.0 : 1.0; }

void BM_RejectSg(benchmark::State& state) {
  const Data& d = Get();
  const DynamicConfig c;
  for (auto _ : state) {
    benchmark::DoNotOptimize(RejectDynamicFeatures(d.prev, d.cur, d.keys, d.detections, Weight, c));
  }
  state.counters["keypoints"] = static_cast<double>(d.keys.size());
}

// The tracking thread's way: the previous pyramid is kept from the last frame, only
// the current one is built.
void BM_RejectSgReusedPyramid(benchmark::State& state) {
  const Data& d = Get();
  const DynamicConfig c;
  const FlowFrame prev{d.prev, BuildFlowPyramid(d.prev)};
  for (auto _ : state) {
    const FlowFrame cur{d.cur, BuildFlowPyramid(d.cur)};
    benchmark::DoNotOptimize(RejectDynamicFeatures(prev, cur, d.keys, d.detections, Weight, c));
  }
}

void BM_RejectSgDepthCheck(benchmark::State& state) {
  const Data& d = Get();
  DynamicConfig c;
  c.refinements.depth_check = true;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        RejectDynamicFeatures(FlowFrame{d.prev, {}}, FlowFrame{d.cur, {}}, d.keys, d.detections, Weight, c, &d.depth));
  }
}

void BM_LkFlow(benchmark::State& state) {
  const Data& d = Get();
  std::vector<cv::Point2f> pts;
  for (const cv::KeyPoint& k : d.keys) pts.push_back(k.pt);
  for (auto _ : state) benchmark::DoNotOptimize(TrackBackward(FlowFrame{d.prev, {}}, FlowFrame{d.cur, {}}, pts));
}

void BM_LkFlowPrebuiltPyramids(benchmark::State& state) {
  const Data& d = Get();
  std::vector<cv::Point2f> pts;
  for (const cv::KeyPoint& k : d.keys) pts.push_back(k.pt);
  const FlowFrame prev{d.prev, BuildFlowPyramid(d.prev)}, cur{d.cur, BuildFlowPyramid(d.cur)};
  for (auto _ : state) benchmark::DoNotOptimize(TrackBackward(prev, cur, pts));
}

void BM_BuildFlowPyramid(benchmark::State& state) {
  const Data& d = Get();
  for (auto _ : state) benchmark::DoNotOptimize(BuildFlowPyramid(d.cur));
}

BENCHMARK(BM_RejectSg)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RejectSgReusedPyramid)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RejectSgDepthCheck)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LkFlow)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LkFlowPrebuiltPyramids)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BuildFlowPyramid)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace sgslam::dynamic
