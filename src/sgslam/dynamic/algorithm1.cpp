// Algorithm 1 (algorithm1.h) with its refinements (refinements.h) called in order.
#include "sgslam/dynamic/algorithm1.h"

#include <algorithm>
#include <stdexcept>

#include "sgslam/common/error.h"
#include "sgslam/common/stats.h"
#include "sgslam/dynamic/refinements.h"

namespace sgslam::dynamic {

Mode ParseMode(const std::string& name) {
  if (name == "none") return Mode::kNone;
  if (name == "semantic") return Mode::kSemantic;
  if (name == "geometric") return Mode::kGeometric;
  if (name == "sg") return Mode::kSg;
  throw ConfigError("dynamic.mode = " + name + ": must be none, semantic, geometric or sg");
}

const char* ModeName(Mode mode) {
  switch (mode) {
    case Mode::kNone: return "none";
    case Mode::kSemantic: return "semantic";
    case Mode::kGeometric: return "geometric";
    case Mode::kSg: return "sg";
  }
  return "?";
}

PairSet TrackPairs(const FlowFrame& prev, const FlowFrame& cur, const std::vector<cv::KeyPoint>& keys,
                   const DynamicConfig& config, const UndistortPointsFn& undistort, const FlowParams& flow) {
  const Stopwatch watch;
  PairSet p;
  p.cur.resize(keys.size());
  std::transform(keys.begin(), keys.end(), p.cur.begin(), [](const cv::KeyPoint& k) { return k.pt; });
  p.flow = TrackBackward(prev, cur, p.cur, flow);  // lines 1-2 (flow.h)
  p.cur_un = p.cur, p.prev_un = p.flow.prev;
  if (undistort && config.refinements.undistort_pairs) undistort(p.cur_un), undistort(p.prev_un);  // R1
  p.ms = watch.ElapsedMs();
  return p;
}

namespace {

// Line 3's RANSAC: the authors' release's settings.
constexpr double kRansacThreshold = 1.0;    // px, OpenCV's symmetric epipolar distance for an inlier
constexpr double kRansacConfidence = 0.99;  // probability of an outlier-free sample (OpenCV's default)
constexpr int kRansacIterations = 1000;     // at most (OpenCV's default)
// R3 (a): pairs outside fresh dynamic boxes needed to fit F on them alone, else on
// all valid pairs, as the release does (OpenCV's RANSAC needs 15).
constexpr int kMinStaticPairs = 20;

// Line 3: F by 7-point RANSAC on the pairs of `fit` (R3; on every valid pair when
// too few), then eq. (4) for every valid pair.
void FitFundamental(const PairSet& pairs, const std::vector<bool>& valid, std::vector<bool>& fit,
                    RejectionResult& r) {
  std::vector<Eigen::Vector2d> p1, p2;
  std::vector<bool> preferred;
  for (size_t i = 0; i < valid.size(); ++i) {
    if (!valid[i]) continue;
    p1.emplace_back(pairs.prev_un[i].x, pairs.prev_un[i].y);
    p2.emplace_back(pairs.cur_un[i].x, pairs.cur_un[i].y);
    preferred.push_back(fit[i]);
  }
  r.fundamental = geometry::EstimateFundamental(
      p1, p2, preferred,
      {kRansacThreshold, kRansacConfidence, kRansacIterations, kMinStaticPairs});
  if (!r.fundamental) return;
  for (size_t i = 0, k = 0; i < valid.size(); ++i) {
    if (valid[i]) r.keypoints[i].distance = geometry::EpipolarDistance(r.fundamental->F_cur_prev, p1[k], p2[k]), ++k;
  }
  if (!r.fundamental->from_static) fit = valid;  // fitted on all: the motion fit of R5 may use all too
}

// Lines 4-14 with threshold eps: kept when d * w < eps (line 6; w = 1 outside
// dynamic boxes and in geometric mode: line 10). R5's evidence comes first; R4 and
// R6 judge the keypoints without d. Returns the number kept.
int Decide(Mode mode, double eps, const DepthEvidence& depth, const DynamicConfig& config,
           std::vector<KeypointVerdict>& verdicts) {
  int kept = 0;
  for (size_t i = 0; i < verdicts.size(); ++i) {
    KeypointVerdict& v = verdicts[i];
    if (depth.moved[i]) {
      v.kept = false, v.why = Why::kDepth;
    } else if (std::isnan(v.distance)) {
      JudgeWithoutDistance(mode, eps, config, v);
    } else {
      const double w = mode == Mode::kSg && !depth.confirmed[i] ? v.weight : 1.0;
      v.kept = v.distance * w < eps;  // lines 6 and 10
      v.why = v.kept ? Why::kStatic : Why::kGeometry;
    }
    kept += v.kept;
  }
  return kept;
}

// The ablation's semantic and none modes (Sec. IV-C): the boxes alone; with too
// few kept all are restored, as the release does (no d to rank by).
void JudgeByBoxes(Mode mode, int min_kept, RejectionResult& r) {
  for (KeypointVerdict& v : r.keypoints) {
    v.kept = mode == Mode::kNone || v.weight <= 1.0;
    v.why = v.kept ? Why::kStatic : Why::kSemantics;
  }
  const auto kept = std::count_if(r.keypoints.begin(), r.keypoints.end(), [](const auto& v) { return v.kept; });
  for (KeypointVerdict& v : r.keypoints) {
    if (kept < min_kept && !v.kept) v.kept = true, v.why = Why::kFallback, ++r.restored;
  }
}

void Count(RejectionResult& r) {
  for (const KeypointVerdict& v : r.keypoints) {
    r.kept += v.kept;
    r.rejected_geometry += v.why == Why::kGeometry;
    r.rejected_semantics += v.why == Why::kSemantics;
    r.rejected_depth += v.why == Why::kDepth;
    r.in_dynamic_boxes += v.weight > 1.0;
  }
}

}  // namespace

RejectionResult JudgePairs(Mode mode, const PairSet& pairs, const std::vector<cv::KeyPoint>& keys,
                           const std::vector<Detection>& detections, const WeightFn& weight,
                           const DynamicConfig& config, const DepthCheckInput* depth, const DynamicPrior* prior,
                           const Algorithm1Params& params) {
  const Stopwatch total;
  RejectionResult r;
  r.eps_used = config.eps_std;
  r.ms.flow = pairs.ms;
  // Line 5-6's w per keypoint (R2, R10).
  const KeypointWeighting w = WeighKeypoints(mode, keys, detections, weight, config, depth);
  r.keypoints.resize(keys.size());
  for (size_t i = 0; i < keys.size(); ++i) r.keypoints[i].weight = w.w[i];
  const FallbackParams& fallback = params.fallback;  // R7; off: nothing restored
  const int min_kept = config.refinements.fallback
                           ? static_cast<int>(std::ceil(fallback.min_kept_ratio * static_cast<double>(keys.size())))
                           : 0;
  if (mode == Mode::kNone || mode == Mode::kSemantic) {
    JudgeByBoxes(mode, min_kept, r);
    Count(r);
    r.ms.total = total.ElapsedMs() + pairs.ms;
    return r;
  }
  if (pairs.cur.size() != keys.size()) throw std::invalid_argument("JudgePairs: one pair per keypoint");
  r.valid_pairs = pairs.flow.valid;

  // Line 3 and eq. (4).
  Stopwatch stage;
  std::vector<bool> valid(keys.size());
  for (size_t i = 0; i < keys.size(); ++i) {
    r.keypoints[i].pair = pairs.flow.status[i];
    r.keypoints[i].prev = pairs.flow.prev[i];
    valid[i] = pairs.flow.status[i] == PairStatus::kOk;
  }
  std::vector<bool> fit = PairsForTheFit(mode, pairs, valid, w, prior);  // R3
  FitFundamental(pairs, valid, fit, r);
  if (r.fundamental && config.refinements.appearance_pairs) {
    MeasureAppearancePairs(pairs, r.fundamental->F_cur_prev, r.keypoints);  // R4
  }
  r.ms.fundamental = stage.ElapsedMs();

  stage.Restart();
  const DepthEvidence evidence = CheckPairDepths(mode, pairs, valid, fit, depth, config, params.depth, r);  // R5
  r.ms.depth = stage.ElapsedMs();

  // Lines 4-14, then the fallback (R7).
  stage.Restart();
  int kept = Decide(mode, r.eps_used, evidence, config, r.keypoints);
  while (kept < min_kept && r.relax_steps < fallback.relax_steps) {
    ++r.relax_steps;
    r.eps_used *= fallback.relax_factor;
    kept = Decide(mode, r.eps_used, evidence, config, r.keypoints);
  }
  if (kept < min_kept) r.restored = RestoreMostStatic(mode, min_kept - kept, r.keypoints);
  Count(r);
  r.ms.decide = stage.ElapsedMs();
  r.ms.total = total.ElapsedMs() + pairs.ms;
  return r;
}

RejectionResult RejectDynamicFeatures(const FlowFrame& prev, const FlowFrame& cur,
                                      const std::vector<cv::KeyPoint>& keys, const std::vector<Detection>& detections,
                                      const WeightFn& weight, const DynamicConfig& config,
                                      const DepthCheckInput* depth, const UndistortPointsFn& undistort,
                                      const Algorithm1Params& params) {
  const Mode mode = ParseMode(config.mode);
  PairSet pairs;
  if (mode == Mode::kGeometric || mode == Mode::kSg) {
    pairs = TrackPairs(prev, cur, keys, config, undistort, params.flow);
  }
  return JudgePairs(mode, pairs, keys, detections, weight, config, depth, nullptr, params);
}

}  // namespace sgslam::dynamic
