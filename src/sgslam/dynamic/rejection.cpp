#include "sgslam/dynamic/rejection.h"

#include <algorithm>
#include <numeric>

#include "sgslam/common/error.h"
#include "sgslam/common/stats.h"

namespace sgslam::dynamic {

namespace {

double EffectiveWeight(Mode mode, const KeypointVerdict& v) { return mode == Mode::kSg ? v.weight : 1.0; }

// Algorithm 1 lines 4-14 with threshold eps, plus the unjudged and depth rules.
int Decide(Mode mode, double eps, const DynamicConfig& c, const std::vector<bool>& moved,
           std::vector<KeypointVerdict>& verdicts) {
  int kept = 0;
  for (size_t i = 0; i < verdicts.size(); ++i) {
    KeypointVerdict& v = verdicts[i];
    if (moved[i]) {
      v.kept = false, v.why = Why::kDepth;
    } else if (std::isnan(v.distance)) {
      if (mode == Mode::kSg && v.weight > 1.0) {
        v.kept = false, v.why = Why::kSemantics;
      } else if (c.reject_unmatched) {
        v.kept = false, v.why = Why::kUnmatched;
      } else {
        v.kept = true, v.why = Why::kUnjudged;
      }
    } else {
      v.kept = v.distance * EffectiveWeight(mode, v) < eps;  // lines 6 and 10
      v.why = v.kept ? Why::kStatic : Why::kGeometry;
    }
    kept += v.kept;
  }
  return kept;
}

// Restores the `missing` rejected keypoints that look most static: finite d * w
// first (smallest first), then those without a test, depth-flagged ones last.
int RestoreMostStatic(Mode mode, int missing, std::vector<KeypointVerdict>& verdicts) {
  auto tier = [](const KeypointVerdict& v) { return v.why == Why::kDepth ? 2 : std::isnan(v.distance) ? 1 : 0; };
  std::vector<size_t> rejected;
  for (size_t i = 0; i < verdicts.size(); ++i) {
    if (!verdicts[i].kept) rejected.push_back(i);
  }
  std::stable_sort(rejected.begin(), rejected.end(), [&](size_t a, size_t b) {
    const KeypointVerdict &va = verdicts[a], &vb = verdicts[b];
    if (tier(va) != tier(vb)) return tier(va) < tier(vb);
    return tier(va) == 0 && va.distance * EffectiveWeight(mode, va) < vb.distance * EffectiveWeight(mode, vb);
  });
  const int n = std::min<int>(missing, static_cast<int>(rejected.size()));
  for (int k = 0; k < n; ++k) verdicts[rejected[k]].kept = true, verdicts[rejected[k]].why = Why::kFallback;
  return n;
}

void Count(RejectionResult& r) {
  for (const KeypointVerdict& v : r.keypoints) {
    r.kept += v.kept;
    r.rejected_geometry += v.why == Why::kGeometry;
    r.rejected_semantics += v.why == Why::kSemantics;
    r.rejected_depth += v.why == Why::kDepth;
    r.rejected_unmatched += v.why == Why::kUnmatched;
    r.in_dynamic_boxes += v.weight > 1.0;
  }
}

}  // namespace

Mode ParseMode(const std::string& name) {
  if (name == "none") return Mode::kNone;
  if (name == "semantic") return Mode::kSemantic;
  if (name == "geometric") return Mode::kGeometric;
  if (name == "sg") return Mode::kSg;
  throw ConfigError("dynamic.mode = " + name + ": must be none, semantic, geometric or sg");
}

RejectionResult RejectDynamicFeatures(const FlowFrame& prev, const FlowFrame& cur,
                                      const std::vector<cv::KeyPoint>& keys, const std::vector<Detection>& detections,
                                      const WeightFn& weight, const DynamicConfig& config,
                                      const DepthCheckInput* depth) {
  const Stopwatch total;
  const Mode mode = ParseMode(config.mode);
  RejectionResult r;
  r.eps_used = config.eps_std;
  const std::vector<double> w = KeypointWeights(keys, detections, weight);
  r.keypoints.resize(keys.size());
  for (size_t i = 0; i < keys.size(); ++i) r.keypoints[i].weight = w[i];
  const int min_kept = static_cast<int>(std::ceil(config.min_kept_ratio * static_cast<double>(keys.size())));

  if (mode == Mode::kNone || mode == Mode::kSemantic) {
    for (KeypointVerdict& v : r.keypoints) {
      v.kept = mode == Mode::kNone || v.weight <= 1.0;
      v.why = v.kept ? Why::kStatic : Why::kSemantics;
    }
    const auto kept = std::count_if(r.keypoints.begin(), r.keypoints.end(), [](const auto& v) { return v.kept; });
    for (KeypointVerdict& v : r.keypoints) {  // no d to rank by: restore all, as the release does
      if (kept < min_kept && !v.kept) v.kept = true, v.why = Why::kFallback, ++r.restored;
    }
    Count(r);
    r.ms.total = total.ElapsedMs();
    return r;
  }

  Stopwatch stage;
  std::vector<cv::Point2f> cur_points(keys.size());
  std::transform(keys.begin(), keys.end(), cur_points.begin(), [](const cv::KeyPoint& k) { return k.pt; });
  const FlowPairs flow = TrackBackward(prev, cur, cur_points, config);  // lines 1-2
  r.valid_pairs = flow.valid;
  r.ms.flow = stage.ElapsedMs();

  stage.Restart();
  std::vector<Eigen::Vector2d> p1, p2;
  std::vector<bool> preferred;  // sg: fit F on pairs outside dynamic boxes (the release's rule)
  std::vector<bool> valid(keys.size());
  for (size_t i = 0; i < keys.size(); ++i) {
    r.keypoints[i].pair = flow.status[i];
    r.keypoints[i].prev = flow.prev[i];
    valid[i] = flow.status[i] == PairStatus::kOk;
    if (!valid[i]) continue;
    p1.emplace_back(flow.prev[i].x, flow.prev[i].y);
    p2.emplace_back(cur_points[i].x, cur_points[i].y);
    preferred.push_back(mode != Mode::kSg || w[i] <= 1.0);
  }
  r.fundamental = EstimateFundamental(p1, p2, preferred, config);  // line 3
  if (r.fundamental) {
    for (size_t i = 0, k = 0; i < keys.size(); ++i) {
      if (valid[i]) r.keypoints[i].distance = EpipolarDistance(r.fundamental->F_cur_prev, p1[k], p2[k]), ++k;
    }
  }
  r.ms.fundamental = stage.ElapsedMs();

  stage.Restart();
  std::vector<bool> moved(keys.size(), false);
  if (config.depth_check && depth != nullptr) {
    const std::vector<DepthResidual> residuals = CheckDepth(flow.prev, cur_points, valid, *depth, config);
    for (size_t i = 0; i < keys.size(); ++i) moved[i] = residuals[i].valid && residuals[i].moved;
  }
  r.ms.depth = stage.ElapsedMs();

  stage.Restart();
  int kept = Decide(mode, r.eps_used, config, moved, r.keypoints);  // lines 4-14
  while (kept < min_kept && r.relax_steps < config.relax_steps) {   // fallback, see the header
    ++r.relax_steps;
    r.eps_used *= config.relax_factor;
    kept = Decide(mode, r.eps_used, config, moved, r.keypoints);
  }
  if (kept < min_kept) r.restored = RestoreMostStatic(mode, min_kept - kept, r.keypoints);
  Count(r);
  r.ms.decide = stage.ElapsedMs();
  r.ms.total = total.ElapsedMs();
  return r;
}

}  // namespace sgslam::dynamic
