#include "sgslam/dynamic/refinements.h"

#include <algorithm>

namespace sgslam::dynamic {

namespace {

// m, R2: a keypoint this far behind its dynamic box's object is background and keeps
// w = 1. A real body is up to this deep (0.3 and 0.45 m measured slightly better on
// dyn_dev's flat cut-outs; docs/algorithm1.md R2).
constexpr double kBoxDepthBand = 0.6;

}  // namespace

KeypointWeighting WeighKeypoints(Mode mode, const std::vector<cv::KeyPoint>& keys,
                                 const std::vector<Detection>& detections, const WeightFn& weight,
                                 const DynamicConfig& config, const DepthCheckInput* depth) {
  const auto weights_of = [&](const std::vector<Detection>& boxes) {
    return mode == Mode::kSg && depth != nullptr  // R2
               ? KeypointWeightsWithDepth(keys, boxes, weight, depth->cur_depth, depth->depth_factor,
                                          config.refinements.box_depth_band ? kBoxDepthBand : 0.0)
               : KeypointWeights(keys, boxes, weight);
  };
  KeypointWeighting out;
  out.w = weights_of(detections);
  if (std::any_of(detections.begin(), detections.end(), [](const Detection& d) { return d.carried > 0; })) {
    std::vector<Detection> fresh;  // R10: carried boxes may have drifted off their object
    for (const Detection& d : detections) {
      if (d.carried == 0) fresh.push_back(d);
    }
    out.w_fresh = weights_of(fresh);
  }
  return out;
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

std::vector<bool> PairsForTheFit(Mode mode, const PairSet& pairs, const std::vector<bool>& valid,
                                 const KeypointWeighting& w, const DynamicPrior* prior) {
  std::vector<bool> fit(valid.size(), false);
  for (size_t i = 0; i < valid.size(); ++i) {
    fit[i] = valid[i] && (mode != Mode::kSg || w.fit()[i] <= 1.0) &&
             !(prior != nullptr && prior->Dynamic(pairs.flow.prev[i]));
  }
  return fit;
}

void MeasureAppearancePairs(const PairSet& pairs, const Eigen::Matrix3d& F, std::vector<KeypointVerdict>& verdicts) {
  for (size_t i = 0; i < verdicts.size(); ++i) {
    if (pairs.flow.status[i] != PairStatus::kAppearance) continue;
    verdicts[i].loose_distance =
        geometry::EpipolarDistance(F, Eigen::Vector2d(pairs.prev_un[i].x, pairs.prev_un[i].y),
                                   Eigen::Vector2d(pairs.cur_un[i].x, pairs.cur_un[i].y));
  }
}

DepthEvidence CheckPairDepths(Mode mode, const PairSet& pairs, const std::vector<bool>& valid,
                              const std::vector<bool>& fit, const DepthCheckInput* depth, const DynamicConfig& config,
                              const DepthCheckParams& params, RejectionResult& r) {
  DepthEvidence e{std::vector<bool>(valid.size(), false), std::vector<bool>(valid.size(), false)};
  if (!config.refinements.depth_check || depth == nullptr) return e;
  r.motion = EstimateMotion(pairs.flow.prev, pairs.prev_un, pairs.cur_un, fit, depth->prev_depth,
                            depth->depth_factor, depth->K);
  if (!r.motion) return e;  // no trustworthy motion: no check this frame
  DepthCheckInput in = *depth;
  in.T_cur_prev = r.motion->T_cur_prev;
  // The median level needs the movers mostly gone from the pairs, which only the
  // boxes of sg give: in geometric mode movers can fill half the frame and lift it.
  in.median_level = mode == Mode::kSg;
  const std::vector<DepthResidual> residuals =
      CheckDepth(pairs.flow.prev, pairs.cur, pairs.prev_un, pairs.cur_un, valid, in, params);
  int checked = 0, flagged = 0;
  for (size_t i = 0; i < valid.size(); ++i) {
    e.moved[i] = residuals[i].valid && residuals[i].moved;
    checked += residuals[i].valid;
    flagged += e.moved[i];
  }
  // The scene is assumed mostly static (as RANSAC does): a check that flags most
  // of it has a wrong motion (PnP on a large moving object) and would keep the
  // mover and drop the background.
  if (flagged > params.max_share * checked) {
    std::fill(e.moved.begin(), e.moved.end(), false);
    r.depth_ignored = true;
  } else if (mode == Mode::kSg && params.confirm_static > 0) {
    // Direct evidence of a static point outweighs the box's prior.
    const double share = params.confirm_static;
    for (size_t i = 0; i < valid.size(); ++i) {
      const DepthResidual& q = residuals[i];
      e.confirmed[i] = q.valid && !q.moved && q.depth_error <= share * q.depth_tolerance &&
                       q.reprojection_error <= share * q.reprojection_tolerance;
    }
  }
  return e;
}

void JudgeWithoutDistance(Mode mode, double eps, const DynamicConfig& config, KeypointVerdict& v) {
  if (mode == Mode::kSg && v.weight > 1.0) {
    v.kept = false, v.why = Why::kSemantics;  // R6: the box is the only evidence
  } else if (config.refinements.appearance_pairs && v.loose_distance >= eps) {  // R4; NaN compares false
    v.kept = false, v.why = Why::kGeometry;
  } else {
    v.kept = true, v.why = Why::kUnjudged;  // R6
  }
}

int RestoreMostStatic(Mode mode, int missing, std::vector<KeypointVerdict>& verdicts) {
  const auto tier = [](const KeypointVerdict& v) { return v.why == Why::kDepth ? 2 : std::isnan(v.distance) ? 1 : 0; };
  const auto dw = [mode](const KeypointVerdict& v) { return v.distance * (mode == Mode::kSg ? v.weight : 1.0); };
  std::vector<size_t> rejected;
  for (size_t i = 0; i < verdicts.size(); ++i) {
    if (!verdicts[i].kept) rejected.push_back(i);
  }
  std::stable_sort(rejected.begin(), rejected.end(), [&](size_t a, size_t b) {
    const KeypointVerdict &va = verdicts[a], &vb = verdicts[b];
    if (tier(va) != tier(vb)) return tier(va) < tier(vb);
    return tier(va) == 0 && dw(va) < dw(vb);
  });
  const int n = std::min<int>(missing, static_cast<int>(rejected.size()));
  for (int k = 0; k < n; ++k) verdicts[rejected[k]].kept = true, verdicts[rejected[k]].why = Why::kFallback;
  return n;
}

}  // namespace sgslam::dynamic
