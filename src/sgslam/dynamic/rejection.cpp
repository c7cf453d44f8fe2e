#include "sgslam/dynamic/rejection.h"

#include <algorithm>
#include <numeric>
#include <optional>
#include <stdexcept>

#include "sgslam/common/error.h"
#include "sgslam/common/stats.h"

namespace sgslam::dynamic {

namespace {

double EffectiveWeight(Mode mode, const KeypointVerdict& v) { return mode == Mode::kSg ? v.weight : 1.0; }

// Algorithm 1 lines 4-14 with threshold eps, plus the unjudged and depth rules.
int Decide(Mode mode, double eps, const DynamicConfig& c, const std::vector<bool>& moved,
           const std::vector<bool>& confirmed, std::vector<KeypointVerdict>& verdicts) {
  int kept = 0;
  for (size_t i = 0; i < verdicts.size(); ++i) {
    KeypointVerdict& v = verdicts[i];
    if (moved[i]) {
      v.kept = false, v.why = Why::kDepth;
    } else if (std::isnan(v.distance)) {
      if (mode == Mode::kSg && v.weight > 1.0) {
        v.kept = false, v.why = Why::kSemantics;
      } else if (c.judge_appearance_pairs && v.loose_distance >= eps) {  // NaN compares false
        v.kept = false, v.why = Why::kGeometry;
      } else {
        v.kept = true, v.why = Why::kUnjudged;
      }
    } else {
      v.kept = v.distance * (confirmed[i] ? 1.0 : EffectiveWeight(mode, v)) < eps;  // lines 6 and 10
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

int DynamicPrior::Memory(cv::Point2f p) const {
  if (cell <= 0 || dynamic.empty()) return 0;
  const int cx = static_cast<int>(p.x) / cell, cy = static_cast<int>(p.y) / cell;
  if (p.x < 0 || p.y < 0 || cx >= dynamic.cols || cy >= dynamic.rows) return 0;
  return dynamic.at<uchar>(cy, cx);
}

DynamicPrior MakeDynamicPrior(const std::vector<cv::KeyPoint>& keys, const RejectionResult& result, cv::Size image,
                              int cell, const DynamicPrior* previous, int memory) {
  DynamicPrior prior;
  if (cell <= 0 || keys.size() != result.keypoints.size()) return prior;
  prior.cell = cell;
  memory = std::clamp(memory, 1, 255);
  const int cols = (image.width + cell - 1) / cell, rows = (image.height + cell - 1) / cell;
  cv::Mat votes(rows, cols, CV_32S, cv::Scalar(0));   // dynamic minus static keypoints
  cv::Mat longest(rows, cols, CV_8U, cv::Scalar(0));  // the most frames left among its dynamic keypoints
  for (size_t i = 0; i < keys.size(); ++i) {
    const int cx = static_cast<int>(keys[i].pt.x) / cell, cy = static_cast<int>(keys[i].pt.y) / cell;
    if (keys[i].pt.x < 0 || keys[i].pt.y < 0 || cx >= cols || cy >= rows) continue;
    const KeypointVerdict& v = result.keypoints[i];
    int left = 0;  // frames this keypoint still counts as dynamic
    if (!v.kept) {
      left = memory;
    } else if (previous != nullptr && v.pair == PairStatus::kOk) {
      left = std::max(0, previous->Memory(v.prev) - 1);
    }
    votes.at<int>(cy, cx) += left > 0 ? 1 : -1;
    uchar& l = longest.at<uchar>(cy, cx);
    l = std::max<uchar>(l, static_cast<uchar>(left));
  }
  prior.dynamic = cv::Mat(rows, cols, CV_8U, cv::Scalar(0));
  longest.copyTo(prior.dynamic, votes > 0);
  return prior;
}

PairSet TrackPairs(const FlowFrame& prev, const FlowFrame& cur, const std::vector<cv::KeyPoint>& keys,
                   const DynamicConfig& config, const UndistortPointsFn& undistort) {
  const Stopwatch watch;
  PairSet p;
  p.cur.resize(keys.size());
  std::transform(keys.begin(), keys.end(), p.cur.begin(), [](const cv::KeyPoint& k) { return k.pt; });
  const bool undistorting = undistort && config.undistort_pairs;
  p.cur_un = p.cur;
  if (undistorting) undistort(p.cur_un);
  p.flow = TrackBackward(prev, cur, p.cur, config);  // lines 1-2
  p.prev_un = p.flow.prev;
  if (undistorting) undistort(p.prev_un);  // failed pairs are undistorted too (cheap, unused)
  p.ms = watch.ElapsedMs();
  return p;
}

namespace {

// Per keypoint, w of the boxes holding it (regions.h), and the w the fits use:
// boxes carried over a missed detection (box_carry.h) weigh their keypoints but do
// not take pairs out of the F and PnP fits, since where they have drifted off their
// object they would leave the fits to what moves.
struct Weights {
  std::vector<double> w;
  std::vector<double> w_fresh;  // without the carried boxes; empty when the frame has none
  const std::vector<double>& fit() const { return w_fresh.empty() ? w : w_fresh; }
};
Weights WeighKeypoints(Mode mode, const std::vector<cv::KeyPoint>& keys, const std::vector<Detection>& detections,
                       const WeightFn& weight, const DynamicConfig& config, const DepthCheckInput* depth) {
  const auto weights_of = [&](const std::vector<Detection>& boxes) {
    return mode == Mode::kSg && depth != nullptr
               ? KeypointWeightsWithDepth(keys, boxes, weight, depth->cur_depth, depth->depth_factor,
                                          config.box_depth_band)
               : KeypointWeights(keys, boxes, weight);
  };
  Weights out;
  out.w = weights_of(detections);
  if (std::any_of(detections.begin(), detections.end(), [](const Detection& d) { return d.carried > 0; })) {
    std::vector<Detection> fresh;
    for (const Detection& d : detections) {
      if (d.carried == 0) fresh.push_back(d);
    }
    out.w_fresh = weights_of(fresh);
  }
  return out;
}

// None and semantic modes: the boxes alone; with too few kept, all restored (no d
// to rank by), as the release does.
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

// Line 3 and eq. (4): F on the preferred pairs (sg: outside dynamic boxes, the
// release's rule; all modes: outside the prior's cells), each pair's distance.
// use_motion: in, the preferred pairs; out, the pairs the motion fits may use.
void FitFundamental(const PairSet& pairs, const std::vector<bool>& valid, const DynamicConfig& config,
                    std::vector<bool>& use_motion, RejectionResult& r) {
  std::vector<Eigen::Vector2d> p1, p2;
  std::vector<bool> preferred;
  for (size_t i = 0; i < valid.size(); ++i) {
    if (!valid[i]) continue;
    p1.emplace_back(pairs.prev_un[i].x, pairs.prev_un[i].y);
    p2.emplace_back(pairs.cur_un[i].x, pairs.cur_un[i].y);
    preferred.push_back(use_motion[i]);
  }
  r.fundamental = geometry::EstimateFundamental(
      p1, p2, preferred,
      {config.ransac_threshold, config.ransac_confidence, config.ransac_iterations, config.min_static_pairs});
  if (!r.fundamental) return;
  const Eigen::Matrix3d& F = r.fundamental->F_cur_prev;
  for (size_t i = 0, k = 0; i < valid.size(); ++i) {
    if (valid[i]) r.keypoints[i].distance = geometry::EpipolarDistance(F, p1[k], p2[k]), ++k;
  }
  if (!r.fundamental->from_static) use_motion = valid;  // too few preferred pairs: all
  if (!config.judge_appearance_pairs) return;
  for (size_t i = 0; i < valid.size(); ++i) {
    if (pairs.flow.status[i] != PairStatus::kAppearance) continue;
    r.keypoints[i].loose_distance =
        geometry::EpipolarDistance(F, Eigen::Vector2d(pairs.prev_un[i].x, pairs.prev_un[i].y),
                                   Eigen::Vector2d(pairs.cur_un[i].x, pairs.cur_un[i].y));
  }
}

// The RGB-D check (depth_check.h) with the PnP motion of the preferred pairs:
// moved[i] where it flags pair i, confirmed[i] where (sg) it passes well within its
// tolerances.
void CheckPairDepths(Mode mode, const PairSet& pairs, const std::vector<bool>& valid,
                     const std::vector<bool>& use_motion, const DepthCheckInput& depth, const DynamicConfig& config,
                     std::vector<bool>& moved, std::vector<bool>& confirmed, RejectionResult& r) {
  r.motion = EstimateMotion(pairs.flow.prev, pairs.prev_un, pairs.cur_un, use_motion, depth.prev_depth,
                            depth.depth_factor, depth.K, config);
  if (!r.motion) return;  // no trustworthy motion: no check this frame
  DepthCheckInput in = depth;
  in.T_cur_prev = r.motion->T_cur_prev;
  // The median level needs the movers mostly gone from the pairs, which only the
  // boxes of sg give: in geometric mode movers can fill half the frame and lift it.
  // (A copy of the config only then: it holds strings, and this runs every frame.)
  std::optional<DynamicConfig> fixed;
  if (mode != Mode::kSg && config.reprojection_median_factor > 0) {
    fixed = config;
    fixed->reprojection_median_factor = 0;
  }
  const std::vector<DepthResidual> residuals =
      CheckDepth(pairs.flow.prev, pairs.cur, pairs.prev_un, pairs.cur_un, valid, in, fixed ? *fixed : config);
  int checked = 0, flagged = 0;
  for (size_t i = 0; i < valid.size(); ++i) {
    moved[i] = residuals[i].valid && residuals[i].moved;
    checked += residuals[i].valid;
    flagged += moved[i];
  }
  // The scene is assumed mostly static (as RANSAC does): a check that flags most
  // of it has a wrong motion (PnP on a large moving object) and would keep the
  // mover and drop the background.
  if (flagged > config.depth_max_share * checked) {
    std::fill(moved.begin(), moved.end(), false);
    r.depth_ignored = true;
  } else if (mode == Mode::kSg && config.confirm_static > 0) {
    // Direct evidence of a static point outweighs the box's prior (dynamic_config.h).
    const double share = config.confirm_static;
    for (size_t i = 0; i < valid.size(); ++i) {
      const DepthResidual& q = residuals[i];
      confirmed[i] = q.valid && !q.moved && q.depth_error <= share * q.depth_tolerance &&
                     q.reprojection_error <= share * q.reprojection_tolerance;
    }
  }
}

}  // namespace

RejectionResult JudgePairs(const PairSet& pairs, const std::vector<cv::KeyPoint>& keys,
                           const std::vector<Detection>& detections, const WeightFn& weight,
                           const DynamicConfig& config, const DepthCheckInput* depth, const DynamicPrior* prior) {
  const Stopwatch total;
  const Mode mode = ParseMode(config.mode);
  RejectionResult r;
  r.eps_used = config.eps_std;
  r.ms.flow = pairs.ms;
  const Weights w = WeighKeypoints(mode, keys, detections, weight, config, depth);
  r.keypoints.resize(keys.size());
  for (size_t i = 0; i < keys.size(); ++i) r.keypoints[i].weight = w.w[i];
  const int min_kept = static_cast<int>(std::ceil(config.min_kept_ratio * static_cast<double>(keys.size())));
  if (mode == Mode::kNone || mode == Mode::kSemantic) {
    JudgeByBoxes(mode, min_kept, r);
    Count(r);
    r.ms.total = total.ElapsedMs() + pairs.ms;
    return r;
  }
  if (pairs.cur.size() != keys.size()) throw std::invalid_argument("JudgePairs: one pair per keypoint");
  r.valid_pairs = pairs.flow.valid;

  Stopwatch stage;
  std::vector<bool> valid(keys.size()), use_motion(keys.size(), false);
  for (size_t i = 0; i < keys.size(); ++i) {
    r.keypoints[i].pair = pairs.flow.status[i];
    r.keypoints[i].prev = pairs.flow.prev[i];
    valid[i] = pairs.flow.status[i] == PairStatus::kOk;
    if (!valid[i]) continue;
    use_motion[i] =
        (mode != Mode::kSg || w.fit()[i] <= 1.0) && !(prior != nullptr && prior->Dynamic(pairs.flow.prev[i]));
  }
  FitFundamental(pairs, valid, config, use_motion, r);  // line 3
  r.ms.fundamental = stage.ElapsedMs();

  stage.Restart();
  std::vector<bool> moved(keys.size(), false), confirmed(keys.size(), false);
  if (config.depth_check && depth != nullptr) {
    CheckPairDepths(mode, pairs, valid, use_motion, *depth, config, moved, confirmed, r);
  }
  r.ms.depth = stage.ElapsedMs();

  stage.Restart();
  int kept = Decide(mode, r.eps_used, config, moved, confirmed, r.keypoints);  // lines 4-14
  while (kept < min_kept && r.relax_steps < config.relax_steps) {   // fallback, see the header
    ++r.relax_steps;
    r.eps_used *= config.relax_factor;
    kept = Decide(mode, r.eps_used, config, moved, confirmed, r.keypoints);
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
                                      const DepthCheckInput* depth, const UndistortPointsFn& undistort) {
  const Mode mode = ParseMode(config.mode);
  PairSet pairs;
  if (mode == Mode::kGeometric || mode == Mode::kSg) pairs = TrackPairs(prev, cur, keys, config, undistort);
  return JudgePairs(pairs, keys, detections, weight, config, depth);
}

}  // namespace sgslam::dynamic
